#pragma once

// The JSON Schema documents of record/schemas/, compiled in (record/CMakeLists.txt makes
// schemas.cpp from them). Use channels() rather than these.

#include <string_view>

namespace wheeltec::record::schemas {

extern const std::string_view telemetry;        // wheeltec.Telemetry.json
extern const std::string_view status;           // wheeltec.Status.json
extern const std::string_view event;            // wheeltec.Event.json
extern const std::string_view pose_in_frame;    // foxglove.PoseInFrame.json
extern const std::string_view frame_transform;  // foxglove.FrameTransform.json

}  // namespace wheeltec::record::schemas
