// The robot registry: adding a robot is one entry here.
#include "predvs/predictors/registry.h"
#include "predvs/servo/free_camera_robot.h"
#include "predvs/servo/robot.h"
#include "predvs/servo/unicycle_tilt_robot.h"
#include "predvs/servo/viper850_robot.h"

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
          {{"viper850", "eye-in-hand 6-DOF Viper850 arm (ViSP kinematic model), joint-velocity command, joint limits"},
           Robots::factory<Viper850Robot>()},
          {{"unicycle-tilt", "unicycle carrying a camera on a tilt joint (paper 001), command (v, omega, tilt rate)"},
           Robots::factory<UnicycleTiltRobot>()},
      });
  return table;
}

}  // namespace

const std::vector<RegistryInfo>& robotRegistry() { return robots().infos(); }
bool isRobot(const std::string& name) { return robots().has(name); }
std::unique_ptr<Robot> makeRobot(const std::string& name, const Params& params) { return robots().make(name, params); }

}  // namespace predvs
