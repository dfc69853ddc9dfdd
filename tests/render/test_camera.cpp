// The pinhole camera's frame (render/camera.h): orthonormal, the image's up toward the camera's up,
// a view straight down or up drawn with -z up instead of refused, degenerate cameras refused.
#include "render/camera.h"

#include <gtest/gtest.h>

namespace pd {
namespace {

void expect_orthonormal(const CameraFrame& f) {
  EXPECT_NEAR(double(length(f.forward)), 1, 1e-6);
  EXPECT_NEAR(double(length(f.right)), 1, 1e-6);
  EXPECT_NEAR(double(length(f.up)), 1, 1e-6);
  EXPECT_NEAR(double(dot(f.forward, f.right)), 0, 1e-6);
  EXPECT_NEAR(double(dot(f.forward, f.up)), 0, 1e-6);
  EXPECT_NEAR(double(dot(f.right, f.up)), 0, 1e-6);
}

TEST(Camera, FrameLooksAtTheTargetWithUpOnTop) {
  Camera c;
  c.eye = {1, 2, 3};
  c.look_at = {0, 0, 0};
  const CameraFrame f = camera_frame(c, 64, 32);
  expect_orthonormal(f);
  EXPECT_NEAR(double(dot(f.forward, normalize(c.look_at - c.eye))), 1, 1e-6);
  EXPECT_GT(double(f.up.y), 0);                                // the world's up is the image's
  EXPECT_NEAR(double(f.half_width / f.half_height), 2, 1e-6);  // the image's aspect
}

TEST(Camera, AViewStraightDownOrUpTakesMinusZAsUp) {
  for (const real dy : {real(-1), real(1)}) {
    Camera c;
    c.eye = {0, 0, 0};
    c.look_at = {0, dy, 0};
    const CameraFrame f = camera_frame(c, 16, 16);
    expect_orthonormal(f);
    EXPECT_NEAR(double(f.up.z), -1, 1e-6) << "view along y " << dy;
  }
}

TEST(Camera, DegenerateCamerasAreRefused) {
  Camera c;
  c.look_at = c.eye;
  EXPECT_THROW(camera_frame(c, 16, 16), std::invalid_argument);
  c.look_at = {0, 0, 0};
  c.eye = {0, 0, 1};
  c.vfov_degrees = 180;
  EXPECT_THROW(camera_frame(c, 16, 16), std::invalid_argument);
  c.vfov_degrees = 40;
  EXPECT_THROW(camera_frame(c, 0, 16), std::invalid_argument);
}

}  // namespace
}  // namespace pd
