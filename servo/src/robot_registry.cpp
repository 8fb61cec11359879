// The robot registry: adding a robot is one entry here.
#include "predvs/predictors/registry.h"
#include "predvs/servo/free_camera_robot.h"
#include "predvs/servo/robot.h"

namespace predvs {
namespace {

using Robots = Registry<Robot, const Params&>;

const Robots& robots() {
  static const Robots table(
      "robot",
      {
          {{"free-camera", "free-flying camera (vpSimulatorCamera), camera-twist command, vpRobot velocity saturation"},
           Robots::factory<FreeCameraRobot>()},
          {{"xy-stage", "camera on an x-y gantry translating parallel to its image plane (paper 000's follower plant)"},
           Robots::factory<XyStageRobot>()},
      });
  return table;
}

}  // namespace

const std::vector<RegistryInfo>& robotRegistry() { return robots().infos(); }
bool isRobot(const std::string& name) { return robots().has(name); }
std::unique_ptr<Robot> makeRobot(const std::string& name, const Params& params) { return robots().make(name, params); }

}  // namespace predvs
