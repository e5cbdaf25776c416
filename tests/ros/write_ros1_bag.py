#!/usr/bin/python3
"""Writes a ROS 1 bag with the official writer (Debian's python3-rosbag) for the tests.

usage: write_ros1_bag.py OUT.bag COMPRESSION TOPIC=CSV... [--string-topic NAME]

Each CSV row is `header_stamp_ns,gx,gy,gz,ax,ay,az` (values written with 17 digits); each row
becomes one sensor_msgs/Imu message of TOPIC, recorded 1 ms after its header stamp.
COMPRESSION is none, bz2 or lz4. --string-topic adds a std_msgs/String topic of three messages.
"""
import sys

import rosbag
import rospy
from sensor_msgs.msg import Imu
from std_msgs.msg import String


def stamp(ns):
    return rospy.Time(secs=ns // 1000000000, nsecs=ns % 1000000000)


def main(argv):
    out, compression, rest = argv[1], argv[2], argv[3:]
    string_topic = None
    if "--string-topic" in rest:
        i = rest.index("--string-topic")
        string_topic = rest[i + 1]
        rest = rest[:i] + rest[i + 2:]
    with rosbag.Bag(out, "w", compression=compression, chunk_threshold=64 * 1024) as bag:
        for spec in rest:
            topic, csv = spec.split("=", 1)
            with open(csv) as f:
                for line in f:
                    v = line.split(",")
                    ns = int(v[0])
                    m = Imu()
                    m.header.stamp = stamp(ns)
                    m.header.frame_id = "imu_link"
                    m.orientation.w = 1.0
                    (m.angular_velocity.x, m.angular_velocity.y,
                     m.angular_velocity.z) = map(float, v[1:4])
                    (m.linear_acceleration.x, m.linear_acceleration.y,
                     m.linear_acceleration.z) = map(float, v[4:7])
                    bag.write(topic, m, stamp(ns + 1000000))
        if string_topic:
            for k in range(3):
                bag.write(string_topic, String(data="hello %d" % k), stamp(1000000000 * (k + 1)))


if __name__ == "__main__":
    main(sys.argv)
