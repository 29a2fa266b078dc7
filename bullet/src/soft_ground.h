#pragma once
// Internal: a coupling's soft ground as a SoilVehicle asks about it. The coupling owns it;
// the vehicle holds it weakly, so a vehicle outliving its coupling asks nothing.

#include <functional>

#include <LinearMath/btVector3.h>

#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

struct SoftGround {
  /// Whether a world point (a wheel's contact) lies on the coupling's deforming ground.
  std::function<bool(const btVector3&)> holds;
};

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
