// Writes the MCAP samples of tests/data/mcap/ with the official writer, @mcap/core, messages
// serialized by Foxglove's @foxglove/rosmsg2-serialization (CDR) from the ROS 2 Humble message
// definitions of @foxglove/rosmsg-msgs-common (tests/data/README.md says how to run it).
//
// usage: node write_mcap.mjs OUT.mcap MODE TOPIC=CSV... [--string-topic NAME]
//   MODE: zstd | lz4 | chunked (uncompressed chunks) | plain (no chunks, no index)
// Each CSV row is `header_stamp_ns,gx,gy,gz,ax,ay,az`; each row one sensor_msgs/msg/Imu,
// logged 1 ms after its header stamp.
import { McapWriter } from "@mcap/core";
import { ros2humble } from "@foxglove/rosmsg-msgs-common";
import { MessageWriter } from "@foxglove/rosmsg2-serialization";
import * as zstd from "@foxglove/wasm-zstd";
import lz4js from "lz4js";
import { open } from "node:fs/promises";
import { readFileSync } from "node:fs";

const [out, mode, ...rest] = process.argv.slice(2);
let stringTopic = null;
const specs = [];
for (let i = 0; i < rest.length; i++) {
  if (rest[i] === "--string-topic") stringTopic = rest[++i];
  else specs.push(rest[i]);
}

// The definitions a writer needs: the root type first, then every type it uses.
function definitions(root) {
  const seen = new Map();
  const visit = (name) => {
    if (seen.has(name)) return;
    const d = ros2humble[name];
    seen.set(name, d);
    for (const f of d.definitions) if (f.isComplex) visit(f.type);
  };
  visit(root);
  return [...seen.values()];
}

await zstd.isLoaded;
const file = await open(out, "w");
let position = 0n;
const writable = {
  position: () => position,
  write: async (buffer) => {
    await file.write(buffer);
    position += BigInt(buffer.byteLength);
  },
};
const compressChunk =
  mode === "zstd"
    ? (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) })
    : mode === "lz4"
      ? (data) => ({ compression: "lz4", compressedData: lz4js.compress(data) })
      : undefined;
const plain = mode === "plain";
const writer = new McapWriter({
  writable,
  useChunks: !plain,
  chunkSize: 32 * 1024,
  compressChunk,
  useMessageIndex: !plain,
  useChunkIndex: !plain,
  useStatistics: !plain,
  useSummaryOffsets: !plain,
  repeatSchemas: !plain,
  repeatChannels: !plain,
});
await writer.start({ profile: "ros2", library: "@mcap/core (allanlot tests)" });

const imuWriter = new MessageWriter(definitions("sensor_msgs/Imu"));
const imuSchema = await writer.registerSchema({
  name: "sensor_msgs/msg/Imu",
  encoding: "ros2msg",
  data: new TextEncoder().encode("# sensor_msgs/msg/Imu (ROS 2 Humble)"),
});
const time = (ns) => ({ sec: Number(ns / 1000000000n), nanosec: Number(ns % 1000000000n) });
for (const spec of specs) {
  const [topic, csv] = spec.split("=");
  const channelId = await writer.registerChannel({
    topic, schemaId: imuSchema, messageEncoding: "cdr", metadata: new Map(),
  });
  let sequence = 0;
  for (const line of readFileSync(csv, "utf8").split("\n")) {
    if (!line) continue;
    const v = line.split(",");
    const ns = BigInt(v[0]);
    const [gx, gy, gz, ax, ay, az] = v.slice(1).map(Number);
    const data = imuWriter.writeMessage({
      header: { stamp: time(ns), frame_id: "imu_link" },
      orientation: { x: 0, y: 0, z: 0, w: 1 },
      orientation_covariance: new Array(9).fill(0),
      angular_velocity: { x: gx, y: gy, z: gz },
      angular_velocity_covariance: new Array(9).fill(0),
      linear_acceleration: { x: ax, y: ay, z: az },
      linear_acceleration_covariance: new Array(9).fill(0),
    });
    await writer.addMessage({
      channelId, sequence: sequence++, logTime: ns + 1000000n, publishTime: ns + 1000000n, data,
    });
  }
}
if (stringTopic) {
  const stringWriter = new MessageWriter(definitions("std_msgs/String"));
  const schemaId = await writer.registerSchema({
    name: "std_msgs/msg/String", encoding: "ros2msg", data: new TextEncoder().encode("string data"),
  });
  const channelId = await writer.registerChannel({
    topic: stringTopic, schemaId, messageEncoding: "cdr", metadata: new Map(),
  });
  for (let k = 1n; k <= 3n; k++)
    await writer.addMessage({
      channelId, sequence: Number(k), logTime: k * 1000000000n, publishTime: k * 1000000000n,
      data: stringWriter.writeMessage({ data: "hello " + k }),
    });
}
await writer.end();
await file.close();
