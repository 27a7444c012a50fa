#!/usr/bin/python3
"""The fleet's reductions (python/tread_wear_fleet/reductions.py) on hand-made replay results with known answers:
wear rates, tread depth from mass, projections to the legal limit, readings fitted on exact lines, outliers."""
import datetime
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))

from tread_wear_fleet import layout, reductions  # noqa: E402

DAY0 = datetime.date(2026, 3, 2)
# A tire of round numbers: 1000 kg/m^3, 0.1 m wide, radius 1/(2 pi) m: 100 kg per m of depth, 0.1 g per um.
TIRE = layout.Tire("tire.yaml", 8e-3, 1000.0, 0.1, 1.0 / (2.0 * math.pi))


def outcome(distance_m, loss_kg, wheels=("left", "right")):
    wheel_results = [{"name": w, "distance_m": distance_m, "mass_loss_kg": loss_kg} for w in wheels]
    return {"result": {"duration_s": 600.0, "wheels": wheel_results}}


def vehicle(days, readings=(), kind=None, vehicle_id="v"):
    """A two-wheel vehicle with one bag per entry of days: (day index, distance_m, loss_kg) or (day index, error)."""
    bags, outcomes = [], {}
    for i, entry in enumerate(days):
        path = f"/fleet/{vehicle_id}/drives/{i}.bag"
        bags.append((DAY0 + datetime.timedelta(days=entry[0]), path))
        outcomes[path] = {"error": entry[1]} if isinstance(entry[1], str) else outcome(entry[1], entry[2])
    v = layout.Vehicle(vehicle_id, "/fleet/" + vehicle_id, "wheels.yaml", {"kind": "test"},
                       [("left", TIRE), ("right", TIRE)], bags, list(readings), kind)
    return v, outcomes


class ReductionTest(unittest.TestCase):
    def test_tire_mass_per_depth(self):
        self.assertAlmostEqual(TIRE.mass_per_depth_kg_per_m(), 100.0, places=12)

    def test_constant_wear_projects_linearly_to_the_limit(self):
        # 10 km a day at 20 mg/km over days 0, 1 and 3 (a day without driving): 30 km, 600 mg = 6 um.
        v, outcomes = vehicle([(0, 10e3, 200e-6), (1, 10e3, 200e-6), (3, 10e3, 200e-6)])
        r = reductions.vehicle_reduction(v, outcomes)
        w = r["wheels"][0]
        self.assertEqual(w["days"], 3)
        self.assertAlmostEqual(w["mg_per_km"], 20.0)
        self.assertAlmostEqual(w["mg_per_km_daily_sd"], 0.0)
        self.assertAlmostEqual(w["model_mm_per_1000km"], 0.2)  # 20 mg/km / 100 kg/m = 0.2 um/km
        self.assertAlmostEqual(w["model_depth_mm"], 8.0 - 0.006)
        self.assertAlmostEqual(w["km_per_day"], 30.0 / 4)  # days 0..3 inclusive
        remaining_km = (8.0 - 0.006 - 1.6) / 0.2 * 1000
        self.assertAlmostEqual(w["model_km_to_limit"], remaining_km, places=6)
        expected = DAY0 + datetime.timedelta(days=3) + datetime.timedelta(days=remaining_km / 7.5)
        self.assertEqual(w["model_date_at_limit"], expected.isoformat())
        self.assertEqual([d["cumulative_distance_km"] for d in w["daily"]], [10.0, 20.0, 30.0])

    def test_spread_of_daily_rates(self):
        v, outcomes = vehicle([(0, 10e3, 100e-6), (1, 10e3, 300e-6)])  # 10 and 30 mg/km
        w = reductions.vehicle_reduction(v, outcomes)["wheels"][0]
        self.assertAlmostEqual(w["mg_per_km"], 20.0)
        self.assertAlmostEqual(w["mg_per_km_daily_sd"], math.sqrt(200.0))

    def test_depth_readings_on_an_exact_line(self):
        # Readings say 1 um per km (5x the model's 0.2): depth 8.000, 7.990, 7.980 mm after 0, 10, 20 km.
        readings = [(DAY0 - datetime.timedelta(days=1), "left", 8.0), (DAY0, "left", 7.99),
                    (DAY0 + datetime.timedelta(days=1), "left", 7.98)]
        v, outcomes = vehicle([(0, 10e3, 200e-6), (1, 10e3, 200e-6)], readings, "tread_depth_mm")
        w = reductions.vehicle_reduction(v, outcomes)["wheels"][0]
        fit = w["readings"]
        self.assertEqual(fit["n"], 3)
        self.assertAlmostEqual(fit["mm_per_1000km"], 1.0, places=9)
        self.assertAlmostEqual(fit["mm_per_1000km_se"], 0.0, places=9)
        self.assertAlmostEqual(fit["depth_end_mm"], 7.98, places=9)
        self.assertAlmostEqual(fit["over_model"], 5.0, places=9)
        self.assertAlmostEqual(fit["km_to_limit"], (7.98 - 1.6) / 1.0 * 1000, places=3)
        self.assertIsNone(reductions.vehicle_reduction(v, outcomes)["wheels"][1]["readings"])

    def test_mass_readings_convert_through_the_tire(self):
        # 2 g lost over 20 km = 20 um over 20 km = 1 um/km; the first reading at the model's depth on its day.
        readings = [(DAY0, "right", 9.0), (DAY0 + datetime.timedelta(days=2), "right", 8.998)]
        v, outcomes = vehicle([(0, 10e3, 200e-6), (1, 10e3, 200e-6), (2, 10e3, 200e-6)], readings, "mass_kg")
        fit = reductions.vehicle_reduction(v, outcomes)["wheels"][1]["readings"]
        self.assertAlmostEqual(fit["mm_per_1000km"], 1.0, places=9)
        self.assertIsNone(fit["mm_per_1000km_se"])  # two readings: no spread
        start_mm = 8.0 - 0.002  # the model's 200 mg = 2 um by the first reading's day
        self.assertAlmostEqual(fit["points"][1]["depth_mm"], start_mm - 0.02, places=9)

    def test_failed_bags_are_listed_and_left_out(self):
        v, outcomes = vehicle([(0, 10e3, 200e-6), (1, "bag data unreadable (corrupt or truncated)")])
        r = reductions.vehicle_reduction(v, outcomes)
        self.assertEqual((r["bags"], r["replayed_bags"], r["drive_time_s"]), (2, 1, 600.0))
        self.assertEqual(r["failures"], [{"bag": "/fleet/v/drives/1.bag",
                                          "reason": "bag data unreadable (corrupt or truncated)"}])
        self.assertAlmostEqual(r["wheels"][0]["distance_km"], 10.0)

    def test_outlier_is_the_vehicle_far_from_the_fleet(self):
        fleet = [{"mean_mg_per_km": x} for x in (10.0, 11.0, 12.0, 10.5, 11.5, 40.0)]
        median, mad = reductions.flag_outliers(fleet)
        self.assertAlmostEqual(median, 11.25)
        self.assertAlmostEqual(mad, 0.75)
        self.assertEqual([v["outlier"] for v in fleet], [False] * 5 + [True])


if __name__ == "__main__":
    unittest.main()
