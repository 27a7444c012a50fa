"""The fleet's output files: CSV tables, the JSON document and the plots (matplotlib, Agg)."""
import csv
import json
import os

from . import diagnosis


def _cell(value):
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.9g}"
    return value


def _write_csv(path, header, rows):
    partial = path + ".tmp"
    with open(partial, "w", newline="") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(header)
        for row in rows:
            writer.writerow([_cell(v) for v in row])
    os.replace(partial, path)


def bag_rows(vehicles, outcomes, fleet_dir):
    """bags.csv: one row per replayed bag and wheel (results only, identical on every run of the same inputs)."""
    for vehicle in vehicles:
        for date, bag in vehicle.bags:
            outcome = outcomes[bag]
            if "error" in outcome:
                continue
            r = outcome["result"]
            for w in r["wheels"]:
                yield [vehicle.vehicle_id, date.isoformat(), os.path.relpath(bag, fleet_dir), w["name"],
                       r["duration_s"], w["distance_m"], w["mass_loss_kg"] * 1e6, w["mg_per_km"],
                       w["stick_fraction_mean"], w["slide_fraction_mean"], w["friction_work_j"], r["bag_sha256"]]


def write_tables(out_dir, document, vehicles, outcomes, fleet_dir):
    """bags.csv, daily.csv, wheels.csv, failures.csv and fleet.json in out_dir."""
    _write_csv(os.path.join(out_dir, "bags.csv"),
               ["vehicle", "date", "bag", "wheel", "duration_s", "distance_m", "mass_loss_mg", "mg_per_km",
                "stick_fraction", "slide_fraction", "friction_work_j", "bag_sha256"],
               bag_rows(vehicles, outcomes, fleet_dir))
    reduced = document["vehicles"]
    _write_csv(os.path.join(out_dir, "daily.csv"),
               ["vehicle", "wheel", "date", "drives", "distance_km", "mass_loss_mg", "mg_per_km",
                "cumulative_distance_km", "model_depth_mm"],
               ([v["vehicle"], w["wheel"], d["date"], d["drives"], d["distance_km"], d["mass_loss_mg"],
                 d["mg_per_km"], d["cumulative_distance_km"], d["model_depth_mm"]]
                for v in reduced for w in v["wheels"] for d in w["daily"]))
    covariates = sorted({k for v in reduced for k in v["covariates"]})
    _write_csv(os.path.join(out_dir, "wheels.csv"),
               ["vehicle"] + covariates + ["wheel", "days", "distance_km", "km_per_day", "mg_per_km",
                                           "mg_per_km_daily_sd", "model_mm_per_1000km", "model_depth_mm",
                                           "model_km_to_limit", "model_date_at_limit", "readings",
                                           "readings_mm_per_1000km", "readings_mm_per_1000km_se",
                                           "readings_over_model", "readings_depth_mm", "readings_km_to_limit",
                                           "readings_date_at_limit", "outlier"],
               ([v["vehicle"]] + [v["covariates"].get(k) for k in covariates] +
                [w["wheel"], w["days"], w["distance_km"], w["km_per_day"], w["mg_per_km"], w["mg_per_km_daily_sd"],
                 w["model_mm_per_1000km"], w["model_depth_mm"], w["model_km_to_limit"], w["model_date_at_limit"]] +
                _readings_cells(w["readings"]) + [int(bool(v.get("outlier")))]
                for v in reduced for w in v["wheels"]))
    _write_csv(os.path.join(out_dir, "failures.csv"), ["vehicle", "bag", "reason"],
               ([f["vehicle"], os.path.relpath(f["bag"], fleet_dir), f["reason"]] for f in document["failures"]))
    if "diagnosis" in document:
        _write_csv(os.path.join(out_dir, "diagnosis.csv"), diagnosis.DIAGNOSIS_HEADER,
                   diagnosis.diagnosis_rows(document["diagnosis"]))
    partial = os.path.join(out_dir, "fleet.json.tmp")
    with open(partial, "w") as f:
        json.dump(document, f, indent=1, sort_keys=True)
    os.replace(partial, os.path.join(out_dir, "fleet.json"))


def _readings_cells(readings):
    if readings is None:
        return [0, None, None, None, None, None, None]
    return [readings["n"], readings["mm_per_1000km"], readings["mm_per_1000km_se"], readings["over_model"],
            readings["depth_end_mm"], readings["km_to_limit"], readings["date_at_limit"]]


def write_plots(out_dir, document):
    """fleet_wear_per_km.png, tread_life.png, outliers.png."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    reduced = document["vehicles"]
    rates = [w["mg_per_km"] for v in reduced for w in v["wheels"] if w["mg_per_km"] is not None]
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.hist(rates, bins=max(5, min(40, len(rates) // 2)), color="tab:blue", alpha=0.8)
    ax.set_xlabel("wear per km of a wheel over all its drives [mg/km]")
    ax.set_ylabel("wheels")
    ax.set_title(f"Fleet distribution of wear per km ({len(reduced)} vehicles, {len(rates)} wheels)")
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "fleet_wear_per_km.png"), dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(7, 4.5))
    limit_mm = document["legal_limit_mm"]
    for v in reduced:
        for w in v["wheels"]:
            if w["model_km_to_limit"] is None:
                continue
            end_km = w["distance_km"] + w["model_km_to_limit"]
            ax.plot([0.0, w["distance_km"], end_km], [w["new_depth_mm"], w["model_depth_mm"], limit_mm],
                    lw=0.8, alpha=0.6)
            if w["readings"]:
                points = w["readings"]["points"]
                ax.plot([p["distance_km"] for p in points], [p["depth_mm"] for p in points], "k.", ms=3)
    ax.axhline(limit_mm, color="tab:red", ls="--", label=f"legal limit {limit_mm:g} mm")
    ax.set_xlabel("distance [km]")
    ax.set_ylabel("tread depth [mm]")
    ax.set_title("Tread-life projections (lines: model, dots: readings)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "tread_life.png"), dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(7, 4))
    names = [v["vehicle"] for v in reduced if v["mean_mg_per_km"] is not None]
    values = [v["mean_mg_per_km"] for v in reduced if v["mean_mg_per_km"] is not None]
    colours = ["tab:red" if v.get("outlier") else "tab:blue" for v in reduced if v["mean_mg_per_km"] is not None]
    ax.scatter(range(len(values)), values, c=colours, s=14, zorder=3)
    if len(names) <= 40:
        ax.set_xticks(range(len(names)), names, rotation=90, fontsize=7)
    fleet = document["fleet"]
    if fleet["median_mg_per_km"] is not None:
        ax.axhline(fleet["median_mg_per_km"], color="k", lw=0.8, label="fleet median")
        if fleet["mad_mg_per_km"]:
            band = document["outlier_robust_z"] * 1.4826 * fleet["mad_mg_per_km"]
            ax.axhspan(fleet["median_mg_per_km"] - band, fleet["median_mg_per_km"] + band, color="0.9", zorder=0,
                       label=f"|robust z| <= {document['outlier_robust_z']:g}")
        ax.legend()
    for i, (name, colour) in enumerate(zip(names, colours)):
        if colour == "tab:red":
            ax.annotate(name, (i, values[i]), fontsize=7)
    ax.set_xlabel("vehicle")
    ax.set_ylabel("mean wear per km over its wheels [mg/km]")
    ax.set_title("Outliers of the fleet (red)")
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "outliers.png"), dpi=110)
    plt.close(fig)
