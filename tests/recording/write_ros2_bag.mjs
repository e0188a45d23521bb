// Writes a ROS 2 bag's messages with independent implementations, for the tests of seqtopo's readers:
// CDR by @foxglove/rosmsg2-serialization, MCAP files by @mcap/core (chunks compressed by @foxglove/wasm-zstd
// or lz4js). Test-only.
//   node write_ros2_bag.mjs RECIPE.json mcap OUT.mcap [zstd|lz4|none] [nostats]   (nostats: no Statistics record)
//   node write_ros2_bag.mjs RECIPE.json cdr OUT.bin      (length-prefixed messages for write_db3.py)
// RECIPE.json: {"topics": [{"name", "type": "sensor_msgs/msg/Image" | ..., "messages": [...]}]}, messages:
//   Image: {"sec", "nanosec", "width", "height", "encoding", "step", "ppm" (P6/P5 file) | "raw" (base64)}
//   CompressedImage: {"sec", "nanosec", "format", "file"}
//   Odometry / PoseStamped: {"sec", "nanosec", "x", "y", "yaw"}
import { readFileSync, writeFileSync, openSync, writeSync, closeSync } from "node:fs";
import { parse } from "@foxglove/rosmsg";
import { MessageWriter } from "@foxglove/rosmsg2-serialization";
import { McapWriter } from "@mcap/core";
import * as zstd from "@foxglove/wasm-zstd";
import lz4 from "lz4js";

const SEP = "\n================================================================================\n";
const TIME = "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec";
const HEADER = "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id";
const POSE = "MSG: geometry_msgs/Pose\nPoint position\nQuaternion orientation" + SEP +
  "MSG: geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z" + SEP +
  "MSG: geometry_msgs/Quaternion\nfloat64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1";
const SCHEMAS = {
  "sensor_msgs/msg/Image": "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\n" +
    "uint32 step\nuint8[] data" + SEP + HEADER + SEP + TIME,
  "sensor_msgs/msg/CompressedImage": "std_msgs/Header header\nstring format\nuint8[] data" + SEP + HEADER + SEP + TIME,
  "nav_msgs/msg/Odometry": "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n" +
    "geometry_msgs/TwistWithCovariance twist" + SEP + HEADER + SEP + TIME + SEP +
    "MSG: geometry_msgs/PoseWithCovariance\nPose pose\nfloat64[36] covariance" + SEP + POSE + SEP +
    "MSG: geometry_msgs/TwistWithCovariance\nTwist twist\nfloat64[36] covariance" + SEP +
    "MSG: geometry_msgs/Twist\nVector3 linear\nVector3 angular" + SEP + "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z",
  "geometry_msgs/msg/PoseStamped": "std_msgs/Header header\ngeometry_msgs/Pose pose" + SEP + HEADER + SEP + TIME + SEP + POSE,
};

// Pixels of a binary PPM (P6) or PGM (P5) file.
function readPnm(path) {
  const b = readFileSync(path);
  const tokens = [];
  let i = 0;
  while (tokens.length < 4) {
    while (b[i] === 0x20 || b[i] === 0x0a || b[i] === 0x0d || b[i] === 0x09) i++;
    if (b[i] === 0x23) { while (b[i] !== 0x0a) i++; continue; }
    let t = "";
    while (b[i] !== 0x20 && b[i] !== 0x0a && b[i] !== 0x0d && b[i] !== 0x09) t += String.fromCharCode(b[i++]);
    tokens.push(t);
  }
  i++;
  return b.subarray(i);
}

function message(type, m) {
  const header = { stamp: { sec: m.sec, nanosec: m.nanosec }, frame_id: "camera" };
  const q = { x: 0, y: 0, z: Math.sin((m.yaw ?? 0) / 2), w: Math.cos((m.yaw ?? 0) / 2) };
  switch (type) {
    case "sensor_msgs/msg/Image": {
      const data = m.ppm ? readPnm(m.ppm) : Buffer.from(m.raw, "base64");
      return { header, height: m.height, width: m.width, encoding: m.encoding, is_bigendian: m.is_bigendian ?? 0,
        step: m.step, data: new Uint8Array(data) };
    }
    case "sensor_msgs/msg/CompressedImage":
      return { header, format: m.format, data: new Uint8Array(readFileSync(m.file)) };
    case "nav_msgs/msg/Odometry":
      return { header, child_frame_id: "base_link",
        pose: { pose: { position: { x: m.x, y: m.y, z: 0 }, orientation: q }, covariance: new Array(36).fill(0) },
        twist: { twist: { linear: { x: 0, y: 0, z: 0 }, angular: { x: 0, y: 0, z: 0 } }, covariance: new Array(36).fill(0) } };
    case "geometry_msgs/msg/PoseStamped":
      return { header, pose: { position: { x: m.x, y: m.y, z: 0 }, orientation: q } };
  }
  throw new Error("unknown type " + type);
}

const [recipePath, mode, out, compression = "zstd", stats = "stats"] = process.argv.slice(2);
const recipe = JSON.parse(readFileSync(recipePath, "utf8"));
// Every message, serialized, in time order (unless the recipe says keep_order).
const all = [];
for (const topic of recipe.topics) {
  const writer = new MessageWriter(parse(SCHEMAS[topic.type], { ros2: true }));
  for (const m of topic.messages) {
    // log_time [ns, a decimal string]: the bag's receive time when it is not the stamp (a stamp of 0).
    const time = m.log_time !== undefined ? BigInt(m.log_time) : BigInt(m.sec) * 1000000000n + BigInt(m.nanosec);
    all.push({ topic: topic.name, type: topic.type, time,
      data: writer.writeMessage(message(topic.type, m)) });
  }
}
// keep_order: stored as the recipe lists them (messages out of time order, as a recorder with late ones writes).
if (!recipe.keep_order) all.sort((a, b) => (a.time < b.time ? -1 : a.time > b.time ? 1 : 0));

if (mode === "cdr") {
  // topics as JSON on the first line, then per message: topic index, time, length (uint32, uint64, uint32 LE), bytes.
  const fd = openSync(out, "w");
  const names = recipe.topics.map((t) => ({ name: t.name, type: t.type }));
  writeSync(fd, JSON.stringify(names) + "\n");
  for (const m of all) {
    const head = Buffer.alloc(16);
    head.writeUInt32LE(recipe.topics.findIndex((t) => t.name === m.topic), 0);
    head.writeBigUInt64LE(m.time, 4);
    head.writeUInt32LE(m.data.byteLength, 12);
    writeSync(fd, head);
    writeSync(fd, m.data);
  }
  closeSync(fd);
} else if (mode === "mcap") {
  await zstd.isLoaded;
  const fd = openSync(out, "w");
  let position = 0n;
  const writable = { position: () => position, write: async (buffer) => { writeSync(fd, buffer); position += BigInt(buffer.byteLength); } };
  const compressChunk = compression === "none" ? undefined : (data) => {
    if (compression === "zstd") return { compression: "zstd", compressedData: zstd.compress(data, 3) };
    const packed = new Uint8Array(lz4.compressBound(data.byteLength) + 64);
    const n = lz4.compressFrame(data, packed);
    return { compression: "lz4", compressedData: packed.subarray(0, n) };
  };
  const writer = new McapWriter({ writable, chunkSize: recipe.chunk_size ?? 1 << 20, compressChunk,
    useStatistics: stats !== "nostats" });
  await writer.start({ profile: "ros2", library: "seqtopo tests (@mcap/core)" });
  const channels = {};
  for (const topic of recipe.topics) {
    const schemaId = await writer.registerSchema({ name: topic.type, encoding: "ros2msg",
      data: new TextEncoder().encode(SCHEMAS[topic.type]) });
    channels[topic.name] = await writer.registerChannel({ topic: topic.name, schemaId, messageEncoding: "cdr", metadata: new Map() });
  }
  let sequence = 0;
  for (const m of all) {
    await writer.addMessage({ channelId: channels[m.topic], sequence: sequence++, logTime: m.time, publishTime: m.time, data: m.data });
  }
  await writer.end();
  closeSync(fd);
} else {
  throw new Error("mode must be mcap or cdr");
}
