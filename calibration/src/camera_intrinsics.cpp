#include "predvs/calibration/camera_intrinsics.h"

namespace predvs {

vpCameraParameters toVispWithoutDistortion(const CameraIntrinsics& camera) {
  vpCameraParameters cam;
  cam.initPersProjWithoutDistortion(camera.fx_px, camera.fy_px, camera.cx_px, camera.cy_px);
  return cam;
}

}  // namespace predvs
