#!/usr/bin/env python3
"""Writes a ROS 2 SQLite bag (.db3, the rosbag2 schema: tables topics and messages) from the CDR messages that
write_ros2_bag.mjs serialized with @foxglove/rosmsg2-serialization. Test-only, Python's own sqlite3.
Usage: write_db3.py MESSAGES.bin OUT.db3
"""
import json
import sqlite3
import struct
import sys

source, out = sys.argv[1], sys.argv[2]
with open(source, "rb") as f:
    topics = json.loads(f.readline())
    body = f.read()
db = sqlite3.connect(out)
db.executescript("""
CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);
CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL, metadata TEXT NOT NULL);
CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, serialization_format TEXT NOT NULL,
                    offered_qos_profiles TEXT NOT NULL, type_description_hash TEXT NOT NULL);
CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, data BLOB NOT NULL);
CREATE INDEX timestamp_idx ON messages (timestamp ASC);
INSERT INTO schema VALUES (4, 'humble');
""")
for k, t in enumerate(topics):
    db.execute("INSERT INTO topics VALUES (?, ?, ?, 'cdr', '', '')", (k + 1, t["name"], t["type"]))
at = 0
while at < len(body):
    topic, time, size = struct.unpack_from("<IQI", body, at)
    at += 16
    db.execute("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", (topic + 1, time, body[at:at + size]))
    at += size
db.commit()
db.close()
