"""Per-vehicle and fleet reductions of the per-bag replay results (docs/fleet.md, "Outputs").

Per vehicle and wheel: a daily series (distance, mass loss, mg/km, model tread depth), the wear rate with its spread
over days, the readings' own rate (least squares of depth over the vehicle's distance) and the projected distance
and date to the legal tread limit. Depth from mass: a uniform layer over the tread, depth = mass / (density x
tread width x 2 pi x radius), as the C++ MaterialParams::massPerDepth_kg_per_m. The tire is taken as new (the tire
file's tread_depth_mm) at the vehicle's first drive unless readings say otherwise.
"""
import datetime
import math
import statistics

LEGAL_LIMIT_M = 1.6e-3  # EU minimum tread depth of passenger-car tires (Directive 89/459/EEC) [m]
OUTLIER_ROBUST_Z = 3.0  # |x - median| / (1.4826 MAD) beyond this: an outlier of the fleet [-]


def _daily(vehicle, outcomes):
    """{wheel: [(date, drives, distance_m, loss_kg)]} of the vehicle's replayed bags, by date."""
    days = {}
    for date, bag in vehicle.bags:
        outcome = outcomes[bag]
        if "error" in outcome:
            continue
        for w in outcome["result"]["wheels"]:
            day = days.setdefault(w["name"], {}).setdefault(date, [0, 0.0, 0.0])
            day[0] += 1
            day[1] += w["distance_m"]
            day[2] += w["mass_loss_kg"]
    return {wheel: [(d, *values) for d, values in sorted(series.items())] for wheel, series in days.items()}


def _fit_line(xs, ys):
    """Least-squares slope and intercept with the slope's standard error (None with fewer than 3 points)."""
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    if sxx <= 0.0:
        return None
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    intercept = my - slope * mx
    if n < 3:
        return slope, intercept, None
    residual = sum((y - intercept - slope * x) ** 2 for x, y in zip(xs, ys))
    return slope, intercept, math.sqrt(residual / (n - 2) / sxx)


def _distance_at(series, date):
    """The wheel's distance driven up to the end of `date` [m]."""
    return sum(distance for d, _, distance, _ in series if d <= date)


def _loss_at(series, date):
    return sum(loss for d, _, _, loss in series if d <= date)


def _readings_fit(vehicle, wheel, tire, series):
    """The readings as depths over the wheel's distance, and their fit: {n, rate_m_per_m, rate_se, depth_end_m}."""
    readings = sorted((d, value) for d, w, value in vehicle.readings if w == wheel)
    if not readings:
        return None
    xs = [_distance_at(series, d) for d, _ in readings]
    if vehicle.reading_kind == "tread_depth_mm":
        depths = [value * 1e-3 for _, value in readings]
    else:  # mass: loss since the first reading, the first at the model's depth on its date
        first_date, first_mass = readings[0]
        start = tire.tread_depth_m - _loss_at(series, first_date) / tire.mass_per_depth_kg_per_m()
        depths = [start - (first_mass - value) / tire.mass_per_depth_kg_per_m() for _, value in readings]
    total = _distance_at(series, datetime.date.max)
    fit = _fit_line(xs, depths) if len(readings) >= 2 else None
    points = [{"date": d.isoformat(), "distance_km": x / 1e3, "depth_mm": y * 1e3}
              for (d, _), x, y in zip(readings, xs, depths)]
    if fit is None:  # one reading (or all at one distance): the model's wear since the last one
        last_loss = (_loss_at(series, datetime.date.max) - _loss_at(series, readings[-1][0]))
        return {"n": len(readings), "points": points, "rate_m_per_m": None, "rate_se_m_per_m": None,
                "depth_end_m": depths[-1] - last_loss / tire.mass_per_depth_kg_per_m()}
    slope, intercept, se = fit
    return {"n": len(readings), "points": points, "rate_m_per_m": -slope, "rate_se_m_per_m": se,
            "depth_end_m": intercept + slope * total}


def _projection(depth_m, rate_m_per_m, km_per_day, last_date):
    """Distance [km] and date at which the tread reaches the legal limit (None when the rate is not positive)."""
    if rate_m_per_m is None or not rate_m_per_m > 0.0:
        return None, None
    remaining_km = max(0.0, depth_m - LEGAL_LIMIT_M) / rate_m_per_m / 1e3
    if not km_per_day > 0.0:
        return remaining_km, None
    try:
        return remaining_km, (last_date + datetime.timedelta(days=remaining_km / km_per_day)).isoformat()
    except OverflowError:  # beyond the year 9999
        return remaining_km, None


def wheel_reduction(vehicle, wheel, tire, series):
    """The wheel's daily series, wear rate with its spread and its tread-life projections."""
    distance = sum(s[2] for s in series)
    loss = sum(s[3] for s in series)
    per_depth = tire.mass_per_depth_kg_per_m()
    daily, cumulative_m, cumulative_kg = [], 0.0, 0.0
    for date, drives, day_m, day_kg in series:
        cumulative_m += day_m
        cumulative_kg += day_kg
        daily.append({"date": date.isoformat(), "drives": drives, "distance_km": day_m / 1e3,
                      "mass_loss_mg": day_kg * 1e6, "mg_per_km": day_kg * 1e9 / day_m if day_m > 0 else None,
                      "cumulative_distance_km": cumulative_m / 1e3,
                      "model_depth_mm": (tire.tread_depth_m - cumulative_kg / per_depth) * 1e3})
    rates = [d["mg_per_km"] for d in daily if d["mg_per_km"] is not None]
    span_days = (series[-1][0] - series[0][0]).days + 1 if series else 0
    km_per_day = distance / 1e3 / span_days if span_days else 0.0
    model_rate = loss / per_depth / distance if distance > 0 else None
    model_depth = tire.tread_depth_m - loss / per_depth
    readings = _readings_fit(vehicle, wheel, tire, series)
    last_date = series[-1][0] if series else None
    km, date = _projection(model_depth, model_rate, km_per_day, last_date)
    result = {"wheel": wheel, "tire": tire.path, "new_depth_mm": tire.tread_depth_m * 1e3, "days": len(series),
              "distance_km": distance / 1e3, "mass_loss_mg": loss * 1e6, "km_per_day": km_per_day,
              "mg_per_km": loss * 1e9 / distance if distance > 0 else None,
              "mg_per_km_daily_sd": statistics.stdev(rates) if len(rates) >= 2 else None,
              "model_mm_per_1000km": model_rate * 1e9 if model_rate is not None else None,
              "model_depth_mm": model_depth * 1e3, "model_km_to_limit": km, "model_date_at_limit": date,
              "daily": daily, "readings": readings}
    if readings is not None:
        rate = readings["rate_m_per_m"] if readings["rate_m_per_m"] is not None else model_rate
        km, date = _projection(readings["depth_end_m"], rate, km_per_day, last_date)
        readings.update({"depth_end_mm": readings["depth_end_m"] * 1e3, "km_to_limit": km, "date_at_limit": date,
                         "mm_per_1000km": None if readings["rate_m_per_m"] is None else readings["rate_m_per_m"] * 1e9,
                         "mm_per_1000km_se": None if readings["rate_se_m_per_m"] is None
                         else readings["rate_se_m_per_m"] * 1e9,
                         "over_model": None if readings["rate_m_per_m"] is None or not model_rate
                         else readings["rate_m_per_m"] / model_rate})
    return result


def vehicle_reduction(vehicle, outcomes):
    """The vehicle's wheels (wheel_reduction), its failures and its mean wear per km."""
    days = _daily(vehicle, outcomes)
    wheels = [wheel_reduction(vehicle, name, tire, days.get(name, [])) for name, tire in vehicle.wheels]
    failures = [{"bag": bag, "reason": outcomes[bag]["error"]} for _, bag in vehicle.bags if "error" in outcomes[bag]]
    rates = [w["mg_per_km"] for w in wheels if w["mg_per_km"] is not None]
    drive_time_s = sum(outcomes[bag]["result"]["duration_s"] for _, bag in vehicle.bags if "error" not in outcomes[bag])
    return {"vehicle": vehicle.vehicle_id, "covariates": vehicle.covariates, "bags": len(vehicle.bags),
            "replayed_bags": len(vehicle.bags) - len(failures), "failures": failures, "drive_time_s": drive_time_s,
            "mean_mg_per_km": sum(rates) / len(rates) if rates else None, "wheels": wheels}


def flag_outliers(vehicles):
    """Marks vehicles whose mean mg/km lies beyond OUTLIER_ROBUST_Z robust z of the fleet's; returns the fleet's
    median and MAD."""
    values = [v["mean_mg_per_km"] for v in vehicles if v["mean_mg_per_km"] is not None]
    if not values:
        return None, None
    median = statistics.median(values)
    mad = statistics.median(abs(x - median) for x in values)
    for v in vehicles:
        x = v["mean_mg_per_km"]
        z = None if x is None or mad <= 0.0 else (x - median) / (1.4826 * mad)
        v["robust_z"] = z
        v["outlier"] = z is not None and abs(z) > OUTLIER_ROBUST_Z
    return median, mad


def fleet_reduction(vehicles, outcomes, counts):
    """The fleet document: every vehicle's reduction, the fleet distribution, outliers, failures, the run's counts."""
    reduced = [vehicle_reduction(v, outcomes) for v in vehicles]
    median, mad = flag_outliers(reduced)
    return {"format": "tread_wear_fleet", "version": 1, "legal_limit_mm": LEGAL_LIMIT_M * 1e3,
            "outlier_robust_z": OUTLIER_ROBUST_Z, "run": counts,
            "fleet": {"vehicles": len(reduced), "median_mg_per_km": median, "mad_mg_per_km": mad,
                      "outliers": [v["vehicle"] for v in reduced if v.get("outlier")]},
            "failures": [dict(f, vehicle=v["vehicle"]) for v in reduced for f in v["failures"]],
            "vehicles": reduced}
