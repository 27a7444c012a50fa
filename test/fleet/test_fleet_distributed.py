#!/usr/bin/python3
"""The fleet on a real Dask cluster on localhost (ctest `fleet_distributed`, docs/fleet.md).

A scheduler and two worker processes (dask-scheduler, dask-worker --no-nanny: a killed worker stays dead) run a
synthetic fleet of 10 drive bags plus a truncated and an empty one; one worker is killed with SIGKILL while it holds
tasks. The outputs must be byte-identical to a serial run in this process, the two bad bags reported by name with the
replay's reason and skipped, and a rerun must replay only the bag that changed. Needs TREAD_WEAR_BIN (the directory
of tread_wear_drive and tread_wear_replay; ctest sets it).
"""
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest

SOURCE_DIR = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
sys.path.insert(0, os.path.join(SOURCE_DIR, "python"))

from tread_wear_fleet import cli, generate  # noqa: E402

RESULT_FILES = ("bags.csv", "daily.csv", "wheels.csv", "failures.csv")
RUN = {"plots": False, "progress": False, "replay_args": ["--preset", "fast"]}
STARTUP_TIMEOUT_S = 30.0


def _read(path):
    with open(path) as f:
        return f.read()


class LocalCluster:
    """A scheduler and two workers as separate processes, as on a real cluster; killed and reaped at exit."""

    def __init__(self, directory):
        self.directory = directory
        self.processes = []
        env = dict(os.environ, PYTHONPATH=os.path.join(SOURCE_DIR, "python"))
        scheduler_file = os.path.join(directory, "scheduler.json")
        self._start(["dask-scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                     "--scheduler-file", scheduler_file], env, "scheduler")
        deadline = time.monotonic() + STARTUP_TIMEOUT_S
        while not os.path.exists(scheduler_file) and time.monotonic() < deadline:
            time.sleep(0.1)
        from distributed import Client

        self.client = Client(scheduler_file=scheduler_file, timeout=STARTUP_TIMEOUT_S)
        self.address = self.client.scheduler.address
        self.workers = [self._start(["dask-worker", self.address, "--nthreads", "1", "--no-nanny", "--no-dashboard",
                                     "--host", "127.0.0.1"], env, f"worker{i}") for i in range(2)]
        self.client.wait_for_workers(2, timeout=STARTUP_TIMEOUT_S)

    def _start(self, command, env, name):
        log = open(os.path.join(self.directory, name + ".log"), "w")
        process = subprocess.Popen(command, env=env, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
        self.processes.append((process, log))
        return process

    def worker_pids(self):
        return self.client.run(os.getpid)

    def close(self):
        self.client.close()
        for process, log in reversed(self.processes):
            if process.poll() is None:
                process.terminate()
                try:
                    process.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    process.kill()
                    process.wait()
            log.close()


class FleetDistributedTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.bin_dir = cli.find_bin_dir(os.environ.get("TREAD_WEAR_BIN"))
        cls.work = tempfile.mkdtemp(prefix="fleet_test_")
        cls.fleet = os.path.join(cls.work, "fleet")
        # 5 vehicles x 2 days: both kinds, all three styles, drives of about 130 s at 50 Hz (~0.5 s of replay each at
        # the preset fast), so that the kill lands inside a replay.
        generate.generate(cls.fleet, SOURCE_DIR, cls.bin_dir, vehicles=5, days=2, drive_s=120, rate_hz=50.0, seed=7,
                          jobs=2, readings=False)
        good = os.path.join(cls.fleet, "v000", "drives", "2026-01-05_0.bag")
        with open(good, "rb") as f:
            head = f.read(os.path.getsize(good) // 2)
        cls.truncated = os.path.join(cls.fleet, "v000", "drives", "2026-01-07_0.bag")
        with open(cls.truncated, "wb") as f:
            f.write(head)
        cls.empty = os.path.join(cls.fleet, "v001", "drives", "2026-01-07_0.bag")
        open(cls.empty, "wb").close()
        cls.serial = cli.run_fleet(cls.fleet, os.path.join(cls.work, "serial"), serial=True, bin_dir=cls.bin_dir,
                                   **RUN)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def _assert_same_results(self, out_dir):
        for name in RESULT_FILES:
            self.assertEqual(_read(os.path.join(self.work, "serial", name)), _read(os.path.join(out_dir, name)),
                             f"{name} differs from the serial run's")

    def test_killed_worker_loses_nothing_and_bad_bags_are_reported(self):
        self.assertEqual(self.serial["run"]["replayed"], 10)
        self.assertTrue(all(v["wheels"][0]["mg_per_km"] > 0 for v in self.serial["vehicles"]))
        cluster = LocalCluster(self.work)
        try:
            pids = cluster.worker_pids()
            killed = {}

            def kill_a_busy_worker():
                deadline = time.monotonic() + 60.0
                while time.monotonic() < deadline and not killed:
                    busy = [address for address, keys in cluster.client.processing().items()
                            if any(str(key).startswith("replay-") for key in keys)]
                    if busy and cluster.client.processing()[busy[0]]:
                        time.sleep(0.2)  # inside its first replay
                        os.kill(pids[busy[0]], signal.SIGKILL)
                        killed["address"] = busy[0]
                    time.sleep(0.02)

            killer = threading.Thread(target=kill_a_busy_worker)
            killer.start()
            out = os.path.join(self.work, "distributed")
            document = cli.run_fleet(self.fleet, out, scheduler=cluster.address, bin_dir=self.bin_dir, **RUN)
            killer.join()
            self.assertIn("address", killed, "no worker was busy to be killed")
            dead = [p for p, _ in cluster.processes[1:] if p.poll() is not None]
            self.assertEqual(len(dead), 1, "exactly the killed worker must be gone")
            self.assertEqual(dead[0].returncode, -signal.SIGKILL)
            # A killed task ran again elsewhere; if the killed worker had already stored its result, the rerun found it.
            run = document["run"]
            self.assertEqual((run["replayed"] + run["cached"], run["failed"]), (10, 2))
            self.assertLessEqual(run["cached"], 1)
            self._assert_same_results(out)
            reasons = {f["bag"]: f["reason"] for f in document["failures"]}
            self.assertEqual(set(reasons), {self.truncated, self.empty})
            self.assertIn("corrupt", reasons[self.truncated])
            self.assertIn("empty", reasons[self.empty])

            # Rerun on what is left of the cluster: nothing replayed again; then one changed bag, replayed alone.
            again = cli.run_fleet(self.fleet, out, scheduler=cluster.address, bin_dir=self.bin_dir, **RUN)
            self.assertEqual((again["run"]["replayed"], again["run"]["cached"], again["run"]["failed"]), (0, 10, 2))
            self._assert_same_results(out)
        finally:
            cluster.close()
        changed = os.path.join(self.fleet, "v002", "drives", "2026-01-06_0.bag")
        shutil.copy(os.path.join(self.fleet, "v001", "drives", "2026-01-06_0.bag"), changed)  # other config
        third = cli.run_fleet(self.fleet, out, serial=True, bin_dir=self.bin_dir, **RUN)
        self.assertEqual((third["run"]["submitted"], third["run"]["replayed"], third["run"]["cached"]), (3, 1, 9))


if __name__ == "__main__":
    unittest.main()
