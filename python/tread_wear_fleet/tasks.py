"""The per-bag task that the workers run: the C++ replay (tread_wear_replay) of one drive bag, cached by content.

A task's result is a plain dict (picklable, JSON-able). The cache key is the SHA-256 of the bag's bytes together with
the replay's identity (payload_id: the replay executable, the package's libraries, the wheel and tire files, the
options), so that a rerun replays only new or changed bags and a rebuilt model replays everything. A bag that the
replay refuses (corrupt, empty, missing topics) gives a result with `error` set to the tool's reason; it is not
cached, so it is tried again on the next run.
"""
import glob
import hashlib
import json
import os
import subprocess
import tempfile

REPLAY_TOOL = "tread_wear_replay"
RESULT_VERSION = 1
_CHUNK_BYTES = 1 << 20


def file_sha256(path):
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(_CHUNK_BYTES), b""):
            digest.update(chunk)
    return digest.hexdigest()


def payload_id(bin_dir, wheels_path, tire_paths, replay_args):
    """Identity of everything besides the bag that decides a replay's result (hex SHA-256)."""
    digest = hashlib.sha256(f"result {RESULT_VERSION}\n".encode())
    libraries = sorted(glob.glob(os.path.join(os.path.dirname(os.path.abspath(bin_dir)), "libtread_wear_*.so*")))
    for path in [os.path.join(bin_dir, REPLAY_TOOL)] + libraries + [wheels_path] + sorted(tire_paths):
        digest.update(f"{os.path.basename(path)} {file_sha256(path)}\n".encode())
    digest.update(json.dumps(list(replay_args)).encode())
    return digest.hexdigest()


def _result(summary, bag_sha256):
    """The part of a replay summary that the fleet keeps: results only, no timings (identical on any run)."""
    wheels = [{key: w[key] for key in ("name", "mass_loss_kg", "distance_m", "mg_per_km", "stick_fraction_mean",
                                       "slide_fraction_mean", "friction_work_j", "samples_rejected", "time_jumps")}
              for w in summary["wheels"]]
    return {"bag_sha256": bag_sha256, "duration_s": summary["duration_s"], "preset": summary["preset"],
            "update_rate_hz": summary["update_rate_hz"], "wheels": wheels}


def tool_reason(stderr, returncode, tool=REPLAY_TOOL):
    """A failed tool's reason: its last line on stderr that is not a warning, without the tool's name."""
    lines = [line for line in stderr.strip().splitlines() if line.strip() and "warning:" not in line]
    reason = lines[-1] if lines else f"{tool} exited with status {returncode}"
    return reason.split(f"{tool}: ", 1)[-1]


def run_tool(command):
    """Runs one of the package's tools as a child process: (CompletedProcess with stderr, its CPU seconds)."""
    before = os.times()
    run = subprocess.run(command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         text=True, check=False)
    after = os.times()
    return run, (after.children_user + after.children_system) - (before.children_user + before.children_system)


def replay_bag(bag_path, wheels_path, bin_dir, cache_dir, config_id, replay_args=()):
    """Replays one bag (or takes its cached result). Returns {bag, cached, result | error, cpu_s}.

    The result is written to cache_dir/<key>.json through a temporary file and os.replace, so that a worker killed
    mid-task leaves no half entry and two workers finishing the same bag write the same bytes.
    """
    bag_path = os.path.abspath(bag_path)
    if not os.path.isfile(bag_path):
        return {"bag": bag_path, "cached": False, "error": "no such file"}
    if os.path.getsize(bag_path) == 0:
        return {"bag": bag_path, "cached": False, "error": "empty file (0 bytes)"}
    bag_sha256 = file_sha256(bag_path)
    key = hashlib.sha256(f"{bag_sha256} {config_id}".encode()).hexdigest()
    entry = os.path.join(cache_dir, key + ".json")
    if os.path.exists(entry):
        with open(entry) as f:
            return {"bag": bag_path, "cached": True, "key": key, "result": json.load(f), "cpu_s": 0.0}
    os.makedirs(cache_dir, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=cache_dir, prefix=".replay-") as scratch:
        summary_path = os.path.join(scratch, "summary.json")
        command = [os.path.join(bin_dir, REPLAY_TOOL), bag_path, "--wheels", wheels_path, "--summary", summary_path,
                   "--threads", "1", "--quiet"] + list(replay_args)
        run, cpu_s = run_tool(command)
        if run.returncode != 0:
            return {"bag": bag_path, "cached": False, "error": tool_reason(run.stderr, run.returncode),
                    "cpu_s": cpu_s}
        with open(summary_path) as f:
            result = _result(json.load(f), bag_sha256)
        partial = os.path.join(scratch, "entry.json")
        with open(partial, "w") as f:
            json.dump(result, f, sort_keys=True)
        os.replace(partial, entry)
    return {"bag": bag_path, "cached": False, "key": key, "result": result, "cpu_s": cpu_s}
