#!/usr/bin/python3
"""Writes a run table (e.g. polishing_runs.csv) as a rosbag in the diagnosis' bag format (docs/diagnosis.md):
each run becomes a steady segment of the node's input topics on wheel "fl" with a measured side force, a load that
alternates +-2 N, the tread temperature, a cycle message and a mass checkpoint at each end.

usage: PYTHONPATH=<devel>/lib/python3/dist-packages ./make_bag.py RUNS.csv OUT.bag
(the package's generated Python messages must be importable)
"""
import csv
import sys

import rosbag
import rospy
from tread_wear.msg import WheelLoad, WheelSlip, WheelSpeed, TreadTemperature
from geometry_msgs.msg import WrenchStamped
from std_msgs.msg import Float64, Int32
if len(sys.argv) != 3:
    sys.exit(__doc__)
rows = [r for r in csv.reader(l for l in open(sys.argv[1]) if not l.startswith("#"))]
h, rows = rows[0], rows[1:]
ix = {k: i for i, k in enumerate(h)}
bag = rosbag.Bag(sys.argv[2], "w")
t = 1000.0  # bag time of the first checkpoint [s] (ros::Time(0) means unset)
mass = 0.1  # tire mass at the first checkpoint [kg]
p = "wheels/fl/"
def put(topic, msg, t):
    bag.write(topic, msg, rospy.Time.from_sec(t))
put(p + "measured/mass", Float64(mass), t)
for r in rows:
    v = float(r[ix["speed_mps"]])
    dur = float(r[ix["duration_s"]])
    put(p + "measured/cycle", Int32(int(r[ix["cycle_id"]])), t)
    for k in range(11):
        tk = t + dur * k / 10.0
        if k < 10:
            put(p + "load", WheelLoad(load_n=float(r[ix["load_n"]]) + (2.0 if k % 2 else -2.0)), tk)
            put(p + "slip", WheelSlip(slip_angle_rad=float(r[ix["slip_angle_rad"]]), slip_ratio=0.0, path_curvature_per_m=1.0 / float(r[ix["path_radius_m"]])), tk)
            put(p + "speed", WheelSpeed(speed_mps=v), tk)
            put(p + "tread_temperature", TreadTemperature(temperature_c=float(r[ix["tread_temperature_c"]])), tk)
            w = WrenchStamped(); w.wrench.force.y = float(r[ix["side_force_n"]]); put(p + "measured/side_force", w, tk)
    t += dur
    mass -= float(r[ix["wear_rate_kg_per_m"]]) * v * dur
    put(p + "measured/mass", Float64(mass), t)
bag.close()
