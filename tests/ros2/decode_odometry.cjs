// Decodes one nav_msgs/msg/Odometry sample from its serialized bytes (hex, encapsulation
// header included) with Foxglove's ROS 2 CDR implementation, which shares no code with
// Cyclone DDS or Fast CDR, and prints it as JSON together with whether the whole payload
// was read and whether writing the message back gives the same bytes.
//
//   node decode_odometry.cjs HEX     (NODE_PATH: the node_modules of package.json)
"use strict";

const { parse } = require("@foxglove/rosmsg");
const { MessageReader, MessageWriter } = require("@foxglove/rosmsg2-serialization");

// nav_msgs/msg/Odometry and what it contains, as ROS 2 concatenates message definitions.
const ODOMETRY_DEFINITION = `
std_msgs/Header header
string child_frame_id
geometry_msgs/PoseWithCovariance pose
geometry_msgs/TwistWithCovariance twist
================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: geometry_msgs/PoseWithCovariance
Pose pose
float64[36] covariance
================================================================================
MSG: geometry_msgs/Pose
Point position
Quaternion orientation
================================================================================
MSG: geometry_msgs/Point
float64 x
float64 y
float64 z
================================================================================
MSG: geometry_msgs/Quaternion
float64 x
float64 y
float64 z
float64 w
================================================================================
MSG: geometry_msgs/TwistWithCovariance
Twist twist
float64[36] covariance
================================================================================
MSG: geometry_msgs/Twist
Vector3 linear
Vector3 angular
================================================================================
MSG: geometry_msgs/Vector3
float64 x
float64 y
float64 z
`;

const hex = process.argv[2];
if (!hex || !/^([0-9a-f]{2})+$/i.test(hex)) {
  process.stderr.write("usage: node decode_odometry.cjs HEX\n");
  process.exit(2);
}
const bytes = Buffer.from(hex, "hex");
const definitions = parse(ODOMETRY_DEFINITION, { ros2: true });
const reader = new MessageReader(definitions);
const message = reader.readMessage(bytes);
const rewritten = Buffer.from(new MessageWriter(definitions).writeMessage(message));
const typedArraysAsArrays = (key, value) => (ArrayBuffer.isView(value) ? Array.from(value) : value);
process.stdout.write(
  JSON.stringify(
    {
      message,
      trailing_bytes: reader.lastReadHadTrailingBytes(),
      rewritten_identical: rewritten.equals(bytes),
      rewritten_hex: rewritten.toString("hex"),
    },
    typedArraysAsArrays,
  ) + "\n",
);
