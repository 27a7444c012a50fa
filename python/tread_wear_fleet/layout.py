"""The fleet directory (docs/fleet.md, "Layout"): vehicles, their drive bags with dates, wheels, tires and readings.

FLEET_DIR/<vehicle_id>/vehicle.yaml        covariates and the wheel configuration's file name
FLEET_DIR/<vehicle_id>/wheels.yaml         tread_wear_replay --wheels configuration (tire files relative to it)
FLEET_DIR/<vehicle_id>/drives/YYYY-MM-DD[_anything].bag   the drives, dated by their file name
FLEET_DIR/<vehicle_id>/readings.csv        optional workshop readings: date,wheel,tread_depth_mm or date,wheel,mass_kg

Every error names the file and what is wrong (FleetError).
"""
import csv
import datetime
import math
import os
import re

import yaml

VEHICLE_FILE = "vehicle.yaml"
DRIVES_DIR = "drives"
READINGS_FILE = "readings.csv"
READING_KINDS = ("tread_depth_mm", "mass_kg")
_BAG_NAME = re.compile(r"^(\d{4}-\d{2}-\d{2})(?:[_T.-].*)?\.bag$")


class FleetError(ValueError):
    """A fleet directory that does not follow the layout; the message names the file."""


class Tire:
    """What the reductions need of a tire file's `material` section (SI units)."""

    def __init__(self, path, depth_m, density_kg_per_m3, width_m, radius_m):
        self.path = path
        self.tread_depth_m = depth_m
        self.rubber_density_kg_per_m3 = density_kg_per_m3
        self.tread_width_m = width_m
        self.rolling_radius_m = radius_m

    def mass_per_depth_kg_per_m(self):
        """Mass of a tread layer of unit depth over the circumference, as MaterialParams::massPerDepth_kg_per_m."""
        return self.rubber_density_kg_per_m3 * self.tread_width_m * 2.0 * math.pi * self.rolling_radius_m


class Vehicle:
    """One vehicle of the fleet: its files, covariates, wheels with their tires, drives and readings."""

    def __init__(self, vehicle_id, directory, wheels_path, covariates, wheels, bags, readings, reading_kind):
        self.vehicle_id = vehicle_id
        self.directory = directory
        self.wheels_path = wheels_path
        self.covariates = covariates
        self.wheels = wheels  # [(name, Tire)] in the configuration's order
        self.bags = bags  # [(date, path)] sorted by date, then name
        self.readings = readings  # [(date, wheel, value)]
        self.reading_kind = reading_kind  # one of READING_KINDS, or None without readings


def _yaml(path):
    try:
        with open(path) as f:
            data = yaml.safe_load(f)
    except OSError as e:
        raise FleetError(f"{path}: cannot read: {e.strerror}") from e
    except yaml.YAMLError as e:
        raise FleetError(f"{path}: not valid YAML: {e}") from e
    if not isinstance(data, dict):
        raise FleetError(f"{path}: expected a mapping at the top level")
    return data


def _date(text, where):
    try:
        return datetime.date.fromisoformat(text.strip())
    except ValueError as e:
        raise FleetError(f"{where}: '{text}' is not a date YYYY-MM-DD") from e


def read_tire(path):
    """The tire file's material section; FleetError naming the key when one is missing or not positive."""
    material = _yaml(path).get("material")
    if not isinstance(material, dict):
        raise FleetError(f"{path}: no 'material' section (tread depth, density, width, radius)")
    values = {}
    for key in ("tread_depth_mm", "rubber_density_kg_per_m3", "tread_width_mm", "rolling_radius_mm"):
        value = material.get(key)
        if not isinstance(value, (int, float)) or not value > 0:
            raise FleetError(f"{path}: material.{key} = {value!r}: must be a number > 0")
        values[key] = float(value)
    return Tire(path, values["tread_depth_mm"] * 1e-3, values["rubber_density_kg_per_m3"],
                values["tread_width_mm"] * 1e-3, values["rolling_radius_mm"] * 1e-3)


def read_wheels(path):
    """[(wheel name, Tire)] of a replay wheel configuration; tire paths are relative to its directory."""
    wheels = _yaml(path).get("wheels")
    if not isinstance(wheels, list) or not wheels:
        raise FleetError(f"{path}: 'wheels' must be a non-empty list")
    result = []
    for i, wheel in enumerate(wheels):
        if not isinstance(wheel, dict) or "name" not in wheel or "tire_params" not in wheel:
            raise FleetError(f"{path}: wheels[{i}] needs 'name' and 'tire_params'")
        tire_path = os.path.join(os.path.dirname(path), str(wheel["tire_params"]))
        result.append((str(wheel["name"]), read_tire(tire_path)))
    return result


def read_readings(path, wheel_names):
    """([(date, wheel, value)], kind) of a readings CSV; kind is the value column's name (READING_KINDS)."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(line for line in f if not line.lstrip().startswith("#")))
    except OSError as e:
        raise FleetError(f"{path}: cannot read: {e.strerror}") from e
    if not rows or len(rows[0]) != 3 or rows[0][:2] != ["date", "wheel"] or rows[0][2] not in READING_KINDS:
        raise FleetError(f"{path}: the header must be date,wheel,tread_depth_mm or date,wheel,mass_kg")
    kind = rows[0][2]
    readings = []
    for line, row in enumerate(rows[1:], start=2):
        where = f"{path}: row {line}"
        if len(row) != 3:
            raise FleetError(f"{where}: expected 3 fields, got {len(row)}")
        if row[1] not in wheel_names:
            raise FleetError(f"{where}: unknown wheel '{row[1]}' (the configuration's: {', '.join(wheel_names)})")
        try:
            value = float(row[2])
        except ValueError as e:
            raise FleetError(f"{where}: {kind} '{row[2]}' is not a number") from e
        if not math.isfinite(value) or value < 0:
            raise FleetError(f"{where}: {kind} = {value}: must be finite and >= 0")
        readings.append((_date(row[0], where), row[1], value))
    return readings, kind


def read_vehicle(directory):
    """The vehicle in `directory` (which holds vehicle.yaml)."""
    meta_path = os.path.join(directory, VEHICLE_FILE)
    meta = _yaml(meta_path)
    vehicle_id = str(meta.get("vehicle_id", os.path.basename(os.path.normpath(directory))))
    covariates = meta.get("covariates", {})
    if not isinstance(covariates, dict):
        raise FleetError(f"{meta_path}: 'covariates' must be a mapping (name: value)")
    wheels_path = os.path.join(directory, str(meta.get("wheels", "wheels.yaml")))
    wheels = read_wheels(wheels_path)
    drives = os.path.join(directory, DRIVES_DIR)
    if not os.path.isdir(drives):
        raise FleetError(f"{directory}: no '{DRIVES_DIR}' directory of drive bags")
    bags = []
    for name in sorted(os.listdir(drives)):
        if not name.endswith(".bag"):
            continue
        match = _BAG_NAME.match(name)
        if not match:
            raise FleetError(f"{os.path.join(drives, name)}: a drive bag's name starts with its date, YYYY-MM-DD")
        bags.append((_date(match.group(1), os.path.join(drives, name)), os.path.join(drives, name)))
    bags.sort()
    readings, kind = [], None
    readings_path = os.path.join(directory, READINGS_FILE)
    if os.path.exists(readings_path):
        readings, kind = read_readings(readings_path, [name for name, _ in wheels])
    return Vehicle(vehicle_id, directory, wheels_path, covariates, wheels, bags, readings, kind)


def read_fleet(fleet_dir):
    """Every vehicle of the fleet directory (its subdirectories with a vehicle.yaml), sorted by id; absolute paths."""
    fleet_dir = os.path.abspath(fleet_dir)
    if not os.path.isdir(fleet_dir):
        raise FleetError(f"{fleet_dir}: not a directory")
    vehicles = [read_vehicle(os.path.join(fleet_dir, name)) for name in sorted(os.listdir(fleet_dir))
                if os.path.isfile(os.path.join(fleet_dir, name, VEHICLE_FILE))]
    if not vehicles:
        raise FleetError(f"{fleet_dir}: no vehicle (a subdirectory with {VEHICLE_FILE})")
    ids = [v.vehicle_id for v in vehicles]
    duplicates = sorted({i for i in ids if ids.count(i) > 1})
    if duplicates:
        raise FleetError(f"{fleet_dir}: vehicle ids used twice: {', '.join(duplicates)}")
    return vehicles
