// predvs — the robot interface and its registry.
//
// A robot takes one command per base period delta, in its own command space (camera twist,
// joint velocities, wheel speeds: CommandSpace in tasks/task.h), and gives the camera pose wMc in
// the world frame. It also reports the Jacobian from its command to the camera twist (camera
// frame), so that a task written for a camera twist (IBVS through vpServo) can drive any robot
// (vpServo's EYEINHAND_L_cVe_eJe form), and its configuration as its encoders would.
//
// World frame conventions: the target moves in the world x-y plane (servo/scene.h). A ground
// robot (the unicycle) drives on the world x-y plane with z up.
//
// Registry: makeRobot(name, params) builds a robot by name; robotRegistry() lists them (`predvs
// list`). A new robot is one file plus one registry line in servo/src/robot_registry.cpp.
#pragma once

#include "predvs/predictors/params.h"
#include "predvs/predictors/registry.h"
#include "predvs/tasks/task.h"

#include <visp3/core/vpHomogeneousMatrix.h>

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace predvs {

class Robot {
 public:
  virtual ~Robot() = default;

  /// Registry name, e.g. "free-camera".
  virtual std::string name() const = 0;
  virtual const CommandSpace& commandSpace() const = 0;

  /// Puts the robot at rest with its camera at wMc, or as close as its kinematics allow (the arm
  /// places its base so that its initial joint configuration has the camera there; the unicycle
  /// takes the position, heading and tilt of the pose). Throws std::invalid_argument when it
  /// cannot (naming the key).
  virtual void reset(const vpHomogeneousMatrix& wMc) = 0;
  /// The command the robot actually executes for `command`: velocity limits, quantisation.
  virtual Eigen::VectorXd limit(const Eigen::VectorXd& command) const { return command; }
  /// Executes `command` (already limited) for dt seconds.
  virtual void step(const Eigen::VectorXd& command, double dt_s) = 0;
  /// True while the robot rests against a hard limit of its configuration (an arm joint at its
  /// stop), where it can no longer execute every command: the loop counts it as a failure of a
  /// positioning run when the scenario asks for outcomes (metrics.h, Outcome). A robot without
  /// hard limits (a velocity bound is not one) never is.
  virtual bool atLimit() const { return false; }

  /// Camera pose in the world frame now.
  virtual vpHomogeneousMatrix cameraPose() const = 0;
  /// 6 x m: the camera twist (v, w) in the camera frame produced by a unit command, now.
  virtual Eigen::MatrixXd cameraJacobian() const = 0;
  /// Configuration as the encoders report it, and its names (arm: joint angles; unicycle: x, y,
  /// heading, tilt; free camera: the camera position and theta-u).
  virtual Eigen::VectorXd state() const = 0;
  virtual std::vector<std::string> stateNames() const = 0;
};

using RobotInfo = RegistryInfo;

const std::vector<RobotInfo>& robotRegistry();
bool isRobot(const std::string& name);
/// Builds robot `name` from `params` (its keys; unknown ones are rejected). Throws
/// std::invalid_argument "unknown robot 'x' (known: ...)" or naming the parameter.
std::unique_ptr<Robot> makeRobot(const std::string& name, const Params& params = {});

}  // namespace predvs
