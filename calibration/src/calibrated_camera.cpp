#include "predvs/calibration/calibrated_camera.h"

namespace predvs {

vpCameraParameters toVispWithoutDistortion(const CalibratedCamera& camera) {
  vpCameraParameters cam;
  cam.initPersProjWithoutDistortion(camera.fx_px, camera.fy_px, camera.cx_px, camera.cy_px);
  return cam;
}

}  // namespace predvs
