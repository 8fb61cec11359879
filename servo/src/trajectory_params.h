// predvs servo (internal) — reading a trajectory's named parameters with the checks every
// trajectory shares, and errors that name the trajectory and the key.
#pragma once

#include "predvs/predictors/params.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace predvs::detail {

/// Parameter `key` of trajectory `traj` (fallback when absent); throws if it is not finite.
inline double finiteParam(const Params& p, const std::string& traj, const std::string& key, double fallback) {
  const double v = p.get(key, fallback);
  if (!std::isfinite(v)) throw std::invalid_argument("trajectory '" + traj + "': parameter '" + key + "' is not finite");
  return v;
}

/// The same, and it must be > 0.
inline double positiveParam(const Params& p, const std::string& traj, const std::string& key, double fallback) {
  const double v = finiteParam(p, traj, key, fallback);
  if (!(v > 0.0)) {
    std::ostringstream msg;
    msg << "trajectory '" << traj << "': parameter '" << key << "' must be > 0, got " << v;
    throw std::invalid_argument(msg.str());
  }
  return v;
}

}  // namespace predvs::detail
