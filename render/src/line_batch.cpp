#include "shore/render/line_batch.h"

namespace shore::render {

void LineBatch::drawLine(const btVector3& from, const btVector3& to, const btVector3& c) {
  ends_.push_back({float(from.x()), float(from.y()), float(from.z()), float(c.x()), float(c.y()), float(c.z())});
  ends_.push_back({float(to.x()), float(to.y()), float(to.z()), float(c.x()), float(c.y()), float(c.z())});
}

void LineBatch::drawContactPoint(const btVector3& point, const btVector3& normal, btScalar distance, int,
                                 const btVector3& colour) {
  drawLine(point, point + normal * distance, colour);
}

}  // namespace shore::render
