#!/usr/bin/env python3
"""Writes a ROS 1 bag with Debian's python3-rosbag from the same recipe as write_ros2_bag.mjs (ROS 2 type names
are mapped to ROS 1's). Test-only.
Usage: write_ros1_bag.py RECIPE.json OUT.bag [bz2|lz4|none]
"""
import base64
import json
import math
import sys

import genpy
import rosbag
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import CompressedImage, Image


def pnm_pixels(path):
    data = open(path, "rb").read()
    tokens, i = [], 0
    while len(tokens) < 4:
        while data[i:i + 1].isspace():
            i += 1
        if data[i:i + 1] == b"#":
            while data[i:i + 1] != b"\n":
                i += 1
            continue
        start = i
        while not data[i:i + 1].isspace():
            i += 1
        tokens.append(data[start:i])
    return data[i + 1:]


def message(kind, m):
    stamp = genpy.Time(m["sec"], m["nanosec"])
    if kind == "sensor_msgs/msg/Image":
        msg = Image()
        msg.height, msg.width, msg.encoding, msg.step = m["height"], m["width"], m["encoding"], m["step"]
        msg.is_bigendian = m.get("is_bigendian", 0)
        msg.data = pnm_pixels(m["ppm"]) if "ppm" in m else base64.b64decode(m["raw"])
    elif kind == "sensor_msgs/msg/CompressedImage":
        msg = CompressedImage()
        msg.format = m["format"]
        msg.data = open(m["file"], "rb").read()
    else:
        msg = Odometry() if kind == "nav_msgs/msg/Odometry" else PoseStamped()
        pose = msg.pose.pose if kind == "nav_msgs/msg/Odometry" else msg.pose
        pose.position.x, pose.position.y = m["x"], m["y"]
        pose.orientation.z, pose.orientation.w = math.sin(m["yaw"] / 2), math.cos(m["yaw"] / 2)
    msg.header.stamp = stamp
    msg.header.frame_id = "camera"
    return msg, stamp


recipe = json.load(open(sys.argv[1]))
compression = sys.argv[3] if len(sys.argv) > 3 else "none"
messages = []
for topic in recipe["topics"]:
    for m in topic["messages"]:
        msg, stamp = message(topic["type"], m)
        messages.append((stamp, topic["name"], msg))
messages.sort(key=lambda x: x[0])
with rosbag.Bag(sys.argv[2], "w", compression=compression) as bag:
    for stamp, name, msg in messages:
        bag.write(name, msg, stamp)
