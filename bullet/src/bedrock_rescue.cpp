#include "bedrock_rescue.h"

#include <algorithm>

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {
namespace {

/// Its fall stopped: no velocity into the ground.
void stop_fall(CoupledBody& body) {
  btVector3 v = body.motion().linear;
  v.setZ(std::max<btScalar>(v.z(), 0));
  body.set_linear_velocity(v);
}

}  // namespace

bool keep_above_bedrock(CoupledBody& body, EnvelopeRaster& envelope, const terrain::Terrain& terrain,
                        std::vector<double>& scratch) {
  if (envelope.empty()) return false;
  scratch.resize(envelope.lower.size());
  terrain.base_heights(envelope, scratch);
  const double soil_depth = terrain.settings().material.soil_depth;
  double depth = 0.0;
  for (std::size_t k = 0; k < envelope.lower.size(); ++k)
    if (envelope.covers(k)) depth = std::max(depth, scratch[k] - soil_depth - envelope.lower[k]);
  if (depth <= 0.0) return false;
  body.translate(btVector3(0, 0, btScalar(depth)));
  stop_fall(body);
  for (std::size_t k = 0; k < envelope.lower.size(); ++k)
    if (envelope.covers(k)) envelope.lower[k] += depth;
  return true;
}

bool rescue_fallen(CoupledBody& body, const terrain::Terrain& terrain, const Region& region) {
  btVector3 lo, hi;
  body.shape()->getAabb(body.pose(), lo, hi);
  const btVector3 c = body.motion().centre;
  if (!region.contains(c.x(), c.y())) return false;
  const std::int64_t i = terrain.column_i(c.x()), j = terrain.column_j(c.y());
  if (lo.z() >= terrain.bedrock(i, j) - 0.01) return false;
  body.translate(btVector3(0, 0, btScalar(terrain.height(i, j) - lo.z())));
  stop_fall(body);
  body.wake();
  return true;
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
