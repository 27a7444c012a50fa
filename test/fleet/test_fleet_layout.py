#!/usr/bin/python3
"""The fleet layout (python/tread_wear_fleet/layout.py): a valid vehicle is read with its dated bags, tires and
readings; each kind of bad input is refused with a message naming the file and the problem."""
import datetime
import os
import shutil
import sys
import tempfile
import unittest

SOURCE_DIR = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
sys.path.insert(0, os.path.join(SOURCE_DIR, "python"))

from tread_wear_fleet import layout  # noqa: E402

TIRE = "passenger_205_55_r16.yaml"
WHEELS = "wheels:\n" + "".join(f"  - {{name: {w}, tire_params: tires/{TIRE}}}\n" for w in ("left", "right"))


class LayoutTest(unittest.TestCase):
    def setUp(self):
        self.fleet = tempfile.mkdtemp(prefix="fleet_layout_")
        self.vehicle = os.path.join(self.fleet, "car1")
        os.makedirs(os.path.join(self.vehicle, "drives"))
        os.makedirs(os.path.join(self.vehicle, "tires"))
        shutil.copy(os.path.join(SOURCE_DIR, "config", "tires", TIRE), os.path.join(self.vehicle, "tires"))
        self.write("vehicle.yaml", "covariates: {kind: compact, payload_kg: 80}\n")
        self.write("wheels.yaml", WHEELS)
        for name in ("2026-02-03_b.bag", "2026-02-01.bag", "2026-02-03_a.bag", "notes.txt"):
            self.write(os.path.join("drives", name), "")

    def tearDown(self):
        shutil.rmtree(self.fleet)

    def write(self, name, text):
        with open(os.path.join(self.vehicle, name), "w") as f:
            f.write(text)

    def assertRefused(self, *fragments):
        with self.assertRaises(layout.FleetError) as caught:
            layout.read_fleet(self.fleet)
        for fragment in fragments:
            self.assertIn(fragment, str(caught.exception))

    def test_a_valid_vehicle(self):
        self.write("readings.csv", "# gauge\ndate,wheel,tread_depth_mm\n2026-02-01,left,7.9\n2026-02-03,right,7.8\n")
        (v,) = layout.read_fleet(self.fleet)
        self.assertEqual(v.vehicle_id, "car1")
        self.assertEqual(v.covariates, {"kind": "compact", "payload_kg": 80})
        self.assertEqual([os.path.basename(b) for _, b in v.bags],
                         ["2026-02-01.bag", "2026-02-03_a.bag", "2026-02-03_b.bag"])
        self.assertEqual(v.bags[0][0], datetime.date(2026, 2, 1))
        self.assertEqual([name for name, _ in v.wheels], ["left", "right"])
        tire = v.wheels[0][1]  # the tire file's material section, in SI units
        self.assertEqual((tire.tread_depth_m, tire.rubber_density_kg_per_m3), (8e-3, 1150.0))
        self.assertAlmostEqual(tire.tread_width_m, 0.105)
        self.assertAlmostEqual(tire.rolling_radius_m, 0.316)
        self.assertEqual(v.reading_kind, "tread_depth_mm")
        self.assertEqual(v.readings[1], (datetime.date(2026, 2, 3), "right", 7.8))

    def test_bad_inputs_are_named(self):
        self.write(os.path.join("drives", "monday.bag"), "")
        self.assertRefused("monday.bag", "YYYY-MM-DD")
        os.remove(os.path.join(self.vehicle, "drives", "monday.bag"))
        self.write(os.path.join("drives", "2026-13-40.bag"), "")
        self.assertRefused("2026-13-40.bag", "is not a date")
        os.remove(os.path.join(self.vehicle, "drives", "2026-13-40.bag"))
        self.write("readings.csv", "date,wheel,depth\n")
        self.assertRefused("readings.csv", "header")
        self.write("readings.csv", "date,wheel,mass_kg\n2026-02-01,front,9.1\n")
        self.assertRefused("readings.csv: row 2", "unknown wheel 'front'")
        self.write("readings.csv", "date,wheel,mass_kg\n2026-02-01,left,heavy\n")
        self.assertRefused("row 2", "'heavy' is not a number")
        os.remove(os.path.join(self.vehicle, "readings.csv"))
        self.write("wheels.yaml", "wheels:\n  - {name: left, tire_params: tires/none.yaml}\n")
        self.assertRefused("none.yaml", "cannot read")
        self.write("wheels.yaml", WHEELS)
        self.write("vehicle.yaml", "covariates: [kind, compact]\n")
        self.assertRefused("vehicle.yaml", "'covariates' must be a mapping")
        shutil.rmtree(os.path.join(self.vehicle, "drives"))
        self.write("vehicle.yaml", "{}\n")
        self.assertRefused("car1", "no 'drives' directory")

    def test_an_empty_fleet_and_duplicate_ids(self):
        os.remove(os.path.join(self.vehicle, "vehicle.yaml"))
        self.assertRefused(self.fleet, "no vehicle")
        self.write("vehicle.yaml", "vehicle_id: same\n")
        shutil.copytree(self.vehicle, os.path.join(self.fleet, "car2"))
        self.assertRefused("vehicle ids used twice: same")


if __name__ == "__main__":
    unittest.main()
