"""Runs the per-bag tasks on Dask distributed (a local cluster, or a running scheduler by address) or serially.

Dask schedules and gathers; when a worker dies its running tasks go to another worker (the scheduler's own
recovery), a task that raises is retried (`retries`), and a bag the replay refuses is an error result, not an
exception. Cached bags whose file (size and modification time) is unchanged since the last run are not submitted at
all (the index in the cache directory); every other bag is hashed by its task.
"""
import json
import os
import sys
import time

from . import tasks

INDEX_FILE = "index.json"


class Progress:
    """One line on a terminal (rewritten), or a line per tenth of the bags otherwise."""

    def __init__(self, total, stream=sys.stderr, enabled=True, unit="bags"):
        self.total, self.stream, self.enabled, self.unit = total, stream, enabled, unit
        self.done = self.failed = self.cached = 0
        self.start = time.monotonic()
        self.tty = enabled and stream.isatty()
        self.last_tenth = 0

    def update(self, outcome):
        self.done += 1
        self.failed += "error" in outcome
        self.cached += bool(outcome.get("cached"))
        if not self.enabled:
            return
        elapsed = time.monotonic() - self.start
        eta = elapsed / self.done * (self.total - self.done)
        line = (f"fleet {self.done}/{self.total} {self.unit} ({self.cached} cached, {self.failed} failed) "
                f"{elapsed:.1f} s, about {eta:.0f} s left")
        if self.tty:
            self.stream.write("\r" + line + ("\n" if self.done == self.total else ""))
        elif self.done * 10 // max(self.total, 1) > self.last_tenth or self.done == self.total:
            self.last_tenth = self.done * 10 // max(self.total, 1)
            self.stream.write(line + "\n")
        self.stream.flush()


def _stat_key(path):
    st = os.stat(path)
    return [st.st_size, st.st_mtime_ns]


def load_index(cache_dir):
    try:
        with open(os.path.join(cache_dir, INDEX_FILE)) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def save_index(cache_dir, index):
    os.makedirs(cache_dir, exist_ok=True)
    partial = os.path.join(cache_dir, INDEX_FILE + ".tmp")
    with open(partial, "w") as f:
        json.dump(index, f, sort_keys=True)
    os.replace(partial, os.path.join(cache_dir, INDEX_FILE))


def _indexed(job, index, cache_dir):
    """The cached outcome of a job whose bag is unchanged since the index was written, else None."""
    seen = index.get(job["bag"])
    if not seen or seen["stat"] != _stat_key(job["bag"]) or seen["config_id"] != job["config_id"]:
        return None
    try:
        with open(os.path.join(cache_dir, seen["key"] + ".json")) as f:
            return {"bag": job["bag"], "cached": True, "key": seen["key"], "result": json.load(f), "cpu_s": 0.0}
    except (OSError, ValueError):
        return None


def _task_args(job, bin_dir, cache_dir):
    return (job["bag"], job["wheels_path"], bin_dir, cache_dir, job["config_id"], job["replay_args"])


def _run_serial(pending, bin_dir, cache_dir, progress):
    outcomes = {}
    for job in pending:
        outcomes[job["bag"]] = tasks.replay_bag(*_task_args(job, bin_dir, cache_dir))
        progress.update(outcomes[job["bag"]])
    return outcomes


def map_tasks(function, named_args, scheduler, workers, retries, on_done, failed):
    """Runs function(*args) for every (name, args) on Dask (the cluster at `scheduler`, else a local one of
    `workers`) and calls on_done(name, outcome) as each completes; a task that fails on every try (or whose workers
    died) gives failed(name, exception) instead of raising. Returns {name: outcome}."""
    from distributed import Client, LocalCluster, as_completed  # only when the engine is used

    cluster = None
    if scheduler:
        client = Client(scheduler)
    else:
        # Workers in this process: each task's work is its own process (the C++ tool), so threads run in parallel,
        # and the cluster starts in a tenth of a second instead of seconds for worker processes.
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=False, dashboard_address=None)
        client = Client(cluster)
    try:
        futures = {client.submit(function, *args, retries=retries, pure=False, key=f"{name}-{n}"): name
                   for n, (name, args) in enumerate(named_args)}
        outcomes = {}
        for future in as_completed(futures):
            name = futures[future]
            try:
                outcomes[name] = future.result()
            except Exception as e:  # the task failed on every try (or its workers died): report, keep the rest
                outcomes[name] = failed(name, e)
            on_done(name, outcomes[name])
        return outcomes
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def _run_dask(pending, bin_dir, cache_dir, progress, scheduler, workers, retries):
    bags = {f"replay-{job['vehicle']}-{os.path.basename(job['bag'])}": job["bag"] for job in pending}
    outcomes = map_tasks(tasks.replay_bag,
                         [(name, _task_args(job, bin_dir, cache_dir)) for name, job in zip(bags, pending)],
                         scheduler, workers, retries, lambda name, outcome: progress.update(outcome),
                         lambda name, e: {"bag": bags[name], "cached": False,
                                          "error": f"task failed: {type(e).__name__}: {e}"})
    return {bags[name]: outcome for name, outcome in outcomes.items()}


def run_jobs(jobs, bin_dir, cache_dir, scheduler=None, workers=2, serial=False, retries=2, progress=True):
    """Outcomes of every job ({bag, vehicle, wheels_path, config_id, replay_args}), keyed by bag path, and the
    run's counts."""
    index = load_index(cache_dir)
    outcomes, pending = {}, []
    for job in jobs:
        known = _indexed(job, index, cache_dir)
        if known is not None:
            outcomes[job["bag"]] = known
        else:
            pending.append(job)
    bar = Progress(len(jobs), enabled=progress)
    for outcome in outcomes.values():
        bar.update(outcome)
    start = time.monotonic()
    if serial or not pending:
        outcomes.update(_run_serial(pending, bin_dir, cache_dir, bar))
    else:
        outcomes.update(_run_dask(pending, bin_dir, cache_dir, bar, scheduler, workers, retries))
    wall_s = time.monotonic() - start
    for job in jobs:
        outcome = outcomes[job["bag"]]
        if "error" not in outcome:
            index[job["bag"]] = {"stat": _stat_key(job["bag"]), "config_id": job["config_id"], "key": outcome["key"]}
    save_index(cache_dir, index)
    counts = {"bags": len(jobs), "submitted": len(pending), "replayed": sum(
        1 for o in outcomes.values() if "error" not in o and not o["cached"]), "cached": sum(
        1 for o in outcomes.values() if o.get("cached")), "failed": sum(1 for o in outcomes.values() if "error" in o),
        "wall_s": wall_s, "replay_cpu_s": sum(o.get("cpu_s", 0.0) for o in outcomes.values())}
    return outcomes, counts
