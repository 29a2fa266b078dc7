#pragma once
// Internal: a coupled body seen from a ground that is not the world's x-y plane
// (shore/bullet/ground_frame.h). It wraps the body's own kind and converts at the border:
// pose, motion and inertia into ground coordinates, impulses and corrections back into the
// world's. The couplings then work in ground coordinates alone. Bodies of a Z-up ground are
// not wrapped (couple(), below), so the default frame adds no operation and no rounding.

#include <memory>
#include <utility>

#include "coupled_body.h"
#include "shore/bullet/ground_frame.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

class FramedBody final : public CoupledBody {
 public:
  FramedBody(std::unique_ptr<CoupledBody> body, const GroundFrame& frame)
      : CoupledBody(body->object(), body->held()),
        body_(std::move(body)),
        frame_(frame),
        to_ground_(frame.to_ground()) {}

  [[nodiscard]] btTransform pose() const override { return to_ground_ * body_->pose(); }
  [[nodiscard]] bool dynamic() const override { return body_->dynamic(); }
  [[nodiscard]] Motion motion() const override {
    const Motion m = body_->motion();
    return {frame_.direction_to_ground(m.linear), frame_.direction_to_ground(m.angular), to_ground_(m.centre)};
  }
  [[nodiscard]] double inverse_mass() const override { return body_->inverse_mass(); }
  [[nodiscard]] btMatrix3x3 inverse_inertia() const override {
    return frame_.rotation.transpose() * body_->inverse_inertia() * frame_.rotation;
  }
  /// The inner body's mobility seen from the ground: each 3 x 3 block turned by R^T . R.
  [[nodiscard]] bool mobility(double a[6][6]) const override {
    double world[6][6];
    if (!body_->mobility(world)) return false;
    const btMatrix3x3& r = frame_.rotation;
    for (int bi = 0; bi < 2; ++bi)
      for (int bj = 0; bj < 2; ++bj)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            double sum = 0.0;  // (R^T B R)_ij = sum_kl R_ki B_kl R_lj
            for (int k = 0; k < 3; ++k)
              for (int l = 0; l < 3; ++l) sum += double(r[k][i]) * world[3 * bi + k][3 * bj + l] * double(r[l][j]);
            a[3 * bi + i][3 * bj + j] = sum;
          }
    return true;
  }
  void apply_impulse(const btVector3& impulse, const btVector3& angular_impulse) override {
    body_->apply_impulse(frame_.direction_to_world(impulse), frame_.direction_to_world(angular_impulse));
  }
  void correct_motion(const btVector3& linear, const btVector3& angular, double h) override {
    body_->correct_motion(frame_.direction_to_world(linear), frame_.direction_to_world(angular), h);
  }
  void stop(double h) override { body_->stop(h); }
  void set_linear_velocity(const btVector3& linear) override {
    body_->set_linear_velocity(frame_.direction_to_world(linear));
  }
  void translate(const btVector3& offset) override { body_->translate(frame_.direction_to_world(offset)); }

  [[nodiscard]] CoupledBody& inner() const noexcept { return *body_; }

 private:
  std::unique_ptr<CoupledBody> body_;
  GroundFrame frame_;
  btTransform to_ground_;
};

/// The body as a coupling on this ground sees it: itself on a Z-up ground, else framed.
inline std::unique_ptr<CoupledBody> couple(std::unique_ptr<CoupledBody> body, const GroundFrame& frame) {
  if (frame.identity()) return body;
  return std::make_unique<FramedBody>(std::move(body), frame);
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
