#!/usr/bin/python3
"""Writes a ROS 2 bag in rosbag2's sqlite3 storage for the tests (python3's sqlite3).

usage: write_ros2_db3.py OUT (a folder: OUT/metadata.yaml and OUT/OUT_0.db3; OUT.db3: the file
alone) TOPIC=CSV... [--string-topic NAME]

The tables are rosbag2's (schema version 3): topics(id, name, type, serialization_format,
offered_qos_profiles) and messages(id, topic_id, timestamp, data). Each CSV row
`header_stamp_ns,gx,gy,gz,ax,ay,az` becomes one sensor_msgs/msg/Imu in CDR (little-endian,
encapsulation 00 01 00 00, fields aligned from after it), received 1 ms after its stamp; the
bytes are those @foxglove/rosmsg2-serialization writes for the same message.
"""
import os
import sqlite3
import struct
import sys


def cdr_string(s, pos):
    b = s.encode() + b"\0"
    return struct.pack("<I", len(b)) + b, pos + 4 + len(b)


def imu_cdr(ns, values):
    out = b"\x00\x01\x00\x00"
    body = struct.pack("<iI", ns // 1000000000, ns % 1000000000)
    frame, pos = cdr_string("imu_link", len(body))
    body += frame
    body += b"\0" * ((8 - pos % 8) % 8)
    doubles = [0.0, 0.0, 0.0, 1.0] + [0.0] * 9 + values[0:3] + [0.0] * 9 + values[3:6] + [0.0] * 9
    return out + body + struct.pack("<37d", *doubles)


def string_cdr(text):
    b = text.encode() + b"\0"
    return b"\x00\x01\x00\x00" + struct.pack("<I", len(b)) + b


def main(argv):
    out, rest = argv[1], argv[2:]
    string_topic = None
    if "--string-topic" in rest:
        i = rest.index("--string-topic")
        string_topic = rest[i + 1]
        rest = rest[:i] + rest[i + 2:]
    if out.endswith(".db3"):
        db_path = out
    else:
        os.makedirs(out, exist_ok=True)
        name = os.path.basename(out.rstrip("/"))
        db_path = os.path.join(out, name + "_0.db3")
        with open(os.path.join(out, "metadata.yaml"), "w") as f:
            f.write("rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n"
                    "  relative_file_paths:\n    - %s_0.db3\n" % name)
    db = sqlite3.connect(db_path)
    db.executescript(
        "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
        "INSERT INTO schema VALUES (3, 'humble');"
        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
        " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
        "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
        " timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
        "CREATE INDEX timestamp_idx ON messages (timestamp ASC);")
    for k, spec in enumerate(rest, start=1):
        topic, csv = spec.split("=", 1)
        db.execute("INSERT INTO topics VALUES (?, ?, 'sensor_msgs/msg/Imu', 'cdr', '')", (k, topic))
        with open(csv) as f:
            for line in f:
                v = line.split(",")
                ns = int(v[0])
                db.execute("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)",
                           (k, ns + 1000000, imu_cdr(ns, [float(x) for x in v[1:7]])))
    if string_topic:
        db.execute("INSERT INTO topics VALUES (99, ?, 'std_msgs/msg/String', 'cdr', '')",
                   (string_topic,))
        for k in range(1, 4):
            db.execute("INSERT INTO messages (topic_id, timestamp, data) VALUES (99, ?, ?)",
                       (k * 1000000000, string_cdr("hello %d" % k)))
    db.commit()
    db.close()


if __name__ == "__main__":
    main(sys.argv)
