#!/usr/bin/python3
"""Live replay through tread_wear_node against the offline tread_wear_replay on the same bag (docs/node.md,
"Replaying fast").

For each play rate R: a private master, `roslaunch tread_wear replay.launch bag:=BAG rate:=R exit_at_end:=false`
(its default clock rate unless --clock-hz is given), the node's /diagnostics followed until the bag has ended
(the clock reached the bag's end and stood still for 2 s) and one more report came,
then one markdown table row: the /clock rate received, live vs offline loss per wheel, stale steps, time jumps,
unaccounted time, the achieved play rate (bag span over the wall time between the wheels' first and last step seen on
`wear`),
and how many wheel reports (after the loss began) and vehicle reports were not OK.

Usage: bench/replay_live_vs_offline.py [--build _build] [--clock-hz HZ] RATE [RATE ...]
The bag and its offline summary are the fast-replay rostest's (BUILD/test_data, made by the build)."""
import argparse
import json
import os
import pathlib
import random
import signal
import subprocess
import sys
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rosgraph_msgs.msg import Clock
from tread_wear.msg import VehicleWear

REPO = pathlib.Path(__file__).resolve().parent.parent


class Watch:
    """The node's wheel reports (last values per wheel), its non-OK counts, the clock's message count and the first
    and last change of the input time the wheels have stepped to (the stamp of `wear`)."""

    def __init__(self):
        self.wheels = {}
        self.not_ok_wheel_reports = 0
        self.not_ok_vehicle_reports = 0
        self.last_report_wall = None
        self.first_clock_wall = None
        self.last_clock_wall = None
        self.clock_messages = 0
        self.first_clock_wall = None
        self.first_step_wall = None
        self.last_step_wall = None
        self.last_step = None
        self.subscribers = [rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics, queue_size=100),
                            rospy.Subscriber("/clock", Clock, self.on_clock, queue_size=1000),
                            rospy.Subscriber("/wear", VehicleWear, self.on_wear, queue_size=100)]

    def on_clock(self, msg):
        self.clock_messages += 1
        if self.first_clock_wall is None:
            self.first_clock_wall = time.monotonic()
        self.last_clock_wall = time.monotonic()

    def on_wear(self, msg):
        if self.last_step is None or msg.header.stamp != self.last_step:
            now = time.monotonic()
            if self.first_step_wall is None and msg.header.stamp.to_sec() > 0.0:
                self.first_step_wall = now
            self.last_step_wall = now
            self.last_step = msg.header.stamp

    def on_diagnostics(self, msg):
        for s in msg.status:
            if ": wheel " in s.name:
                name = s.name.split(": wheel ", 1)[1]
                self.wheels[name] = {kv.key: kv.value for kv in s.values}
                loss_started = float(self.wheels[name]["accumulated loss [kg]"]) > 0.0
                if loss_started and s.level != DiagnosticStatus.OK:
                    self.not_ok_wheel_reports += 1
            elif s.name.endswith(": vehicle") and s.level != DiagnosticStatus.OK and self.wheels:
                self.not_ok_vehicle_reports += 1
        self.last_report_wall = time.monotonic()


def losses(watch):
    return {n: float(v["accumulated loss [kg]"]) for n, v in watch.wheels.items()}


def replay(args, rate, offline, env):
    launch = ["roslaunch", "tread_wear", "replay.launch", "bag:=" + args.bag, "rate:=%g" % rate,
              "exit_at_end:=false"]
    if args.clock_hz:
        launch.append("clock_hz:=%g" % args.clock_hz)
    log = open(os.path.join(env["ROS_HOME"], "replay_r%g.log" % rate), "w")
    proc = subprocess.Popen(launch, env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    watch = Watch()
    try:
        # Until the wheels have stepped to the bag's end (the player stays alive, so the clock runs on) and a report
        # came after that.
        period_s = 1.0 / update_rate_hz(rate)
        deadline = time.monotonic() + 60.0 + 2.0 * offline["duration_s"] / min(rate, 10.0)
        while time.monotonic() < deadline:
            time.sleep(0.5)
            if watch.last_step is not None and watch.last_step.to_sec() >= offline["end_s"] - period_s - 1e-6 and \
                    watch.last_report_wall is not None and watch.last_report_wall > watch.last_step_wall + 1.0:
                break
        else:
            print("rate %g: the replay did not finish in time" % rate, file=sys.stderr)
    finally:
        for subscriber in watch.subscribers:
            subscriber.unregister()
        os.killpg(proc.pid, signal.SIGINT)
        proc.wait(timeout=30)
        log.close()
    return watch


def update_rate_hz(rate):
    """replay.launch's default update_rate_hz at play rate `rate`."""
    return min(100.0, max(5.0, 500.0 / rate))


def offline_losses(build, bag, rate_hz):
    """The offline replay's loss per wheel at the live wheels' update rate (tread_wear_replay --rate-hz)."""
    summary = build / "ros_home" / ("offline_%g_hz.json" % rate_hz)
    subprocess.run([str(build / "devel/lib/tread_wear/tread_wear_replay"), bag, "--quiet", "--rate-hz", "%g" % rate_hz,
                    "--summary", str(summary)], check=True, stdout=subprocess.DEVNULL)
    return {w["name"]: w["mass_loss_kg"] for w in json.load(open(summary))["wheels"]}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=str(REPO / "_build"))
    parser.add_argument("--clock-hz", type=float, default=0.0, help="replay.launch clock_hz (default: its own)")
    parser.add_argument("rates", type=float, nargs="+")
    args = parser.parse_args()
    build = pathlib.Path(args.build).resolve()
    args.bag = str(build / "test_data/wltc_first_300s.bag")
    offline = json.load(open(build / "test_data/wltc_first_300s_offline.json"))
    reference = {w["name"]: w["mass_loss_kg"] for w in offline["wheels"]}

    port = random.randint(20000, 40000)
    env = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:%d" % port, ROS_IP="127.0.0.1",
               ROS_HOME=str(build / "ros_home"))
    os.makedirs(env["ROS_HOME"], exist_ok=True)
    os.environ.update(env)
    core = subprocess.Popen(["roscore", "-p", str(port)], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        time.sleep(3.0)
        rospy.init_node("replay_live_vs_offline", anonymous=True, disable_signals=True)
        print("| R | update rate [Hz] | /clock received [Hz] | live vs offline (100 Hz) loss per wheel "
              "| live vs offline at the same update rate, worst wheel | stale steps | steps past a lagging input "
              "| time jumps fwd / back | unaccounted [s] | achieved rate | non-OK wheel / vehicle reports |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        for rate in args.rates:
            watch = replay(args, rate, offline, env)
            if not watch.wheels:
                print("| %g | no diagnostics |" % rate)
                continue
            live = losses(watch)
            deviation = ["%+.2f %%" % (100.0 * (live[n] / reference[n] - 1.0)) for n in reference if n in live]
            update_hz = update_rate_hz(rate)
            same_rate = offline_losses(build, args.bag, update_hz)
            worst_same = max((abs(live[n] / same_rate[n] - 1.0) for n in same_rate if n in live), default=float("nan"))
            stale = max(int(v["stale steps"]) for v in watch.wheels.values())
            past = max(int(v.get("steps past a lagging input", 0)) for v in watch.wheels.values())
            jumps = "%d / %d" % (max(int(v["time jumps forward"]) for v in watch.wheels.values()),
                                 max(int(v["time jumps backward"]) for v in watch.wheels.values()))
            unaccounted = max(float(v["unaccounted time [s]"]) for v in watch.wheels.values())
            span = (watch.last_step_wall or 0.0) - (watch.first_step_wall or 0.0)
            achieved = offline["duration_s"] / span if span > 0.0 else 0.0
            clock_span = (watch.last_clock_wall or 0.0) - (watch.first_clock_wall or 0.0)
            clock_hz = watch.clock_messages / clock_span if clock_span > 0.0 else 0.0
            print("| %g | %g | %.0f | %s | %.4f %% | %d | %d | %s | %.2f | %.0f | %d / %d |" % (
                rate, update_hz, clock_hz, ", ".join(deviation), 100.0 * worst_same, stale, past, jumps, unaccounted,
                achieved,
                watch.not_ok_wheel_reports, watch.not_ok_vehicle_reports), flush=True)
    finally:
        rospy.signal_shutdown("done")
        os.killpg(core.pid, signal.SIGINT)
        core.wait(timeout=30)


if __name__ == "__main__":
    main()
