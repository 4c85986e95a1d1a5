#include "model_selection.hpp"

namespace wheeltec::emulator {

std::variant<const RobotModel*, std::string> select_model(const std::optional<std::string>& model_name,
                                                          std::optional<ChassisType> chassis) {
  if (!model_name) return &mini_model(chassis.value_or(ChassisType::mecanum));
  const RobotModel* model = find_robot_model(*model_name);
  if (model == nullptr) return "--model: unknown robot model " + *model_name + " (see --list-models)";
  if (chassis && *chassis != model->type) {
    return "--chassis " + std::string(to_string(*chassis)) + " contradicts --model " + *model_name +
           " (whose chassis is " + std::string(to_string(model->type)) + ")";
  }
  return model;
}

}  // namespace wheeltec::emulator
