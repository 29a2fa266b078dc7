#include "report.h"

#include <algorithm>
#include <fstream>
#include <numeric>

#include <btBulletDynamicsCommon.h>

#include "shore/core/error.h"
#include "shore/scenes/world.h"

namespace shore::viewer {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
double mean(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

}  // namespace

void RunReport::frame(const Session& s, double frame_ms) {
  frame_ms_.push_back(frame_ms);
  draw_ms_.push_back(s.last_draw_ms());
  soil_bytes_.push_back(double(s.renderer().stats().soil_bytes));
  whole_soil_bytes_ = double(s.renderer().stats().whole_soil_bytes);
  surface_triangles_.push_back(double(s.renderer().stats().surface_triangles));
  full_triangles_ = double(s.renderer().stats().full_triangles);
}

void RunReport::write(const std::filesystem::path& file, const Session& s, int width, int height) const {
  nlohmann::json j;
  j["scene"] = s.scene_name();
  j["frames"] = frame_ms_.size();
  j["width"] = width;
  j["height"] = height;
  j["frame_ms_median"] = median(frame_ms_);
  j["draw_ms_median"] = median(draw_ms_);
  // The first frame uploads every chunk; the steady state is what the later frames cost.
  const std::vector<double> later(soil_bytes_.begin() + std::min<std::size_t>(1, soil_bytes_.size()),
                                  soil_bytes_.end());
  j["soil_bytes_first_frame"] = soil_bytes_.empty() ? 0.0 : soil_bytes_.front();
  j["soil_bytes_per_frame_mean"] = mean(later);
  j["soil_bytes_per_frame_max"] = later.empty() ? 0.0 : *std::max_element(later.begin(), later.end());
  j["whole_soil_bytes"] = whole_soil_bytes_;
  j["surface_triangles_mean"] = mean(surface_triangles_);
  j["full_triangles"] = full_triangles_;
  j["sim_seconds"] = s.sim_time();
  nlohmann::json bodies = nlohmann::json::array();
  if (s.contents().world != nullptr)
    for (const btRigidBody* b : s.contents().world->bodies()) {
      if (b->isStaticObject()) continue;
      const btVector3 c = b->getCenterOfMassPosition();
      const Eigen::Vector2d px = s.project({c.x(), c.y(), c.z()}, width, height);
      bodies.push_back({{"world", {c.x(), c.y(), c.z()}}, {"pixel", {px.x(), px.y()}}});
    }
  j["bodies"] = bodies;
  const scenes::Bounds& b = s.contents().bounds;
  const Eigen::Vector2d centre = s.project({0.5 * (b.x0 + b.x1), 0.5 * (b.y0 + b.y1), 0.0}, width, height);
  j["bounds_centre_pixel"] = {centre.x(), centre.y()};
  std::ofstream out(file);
  if (!out) throw FileError("viewer.report: cannot write " + file.string());
  out << j.dump(2) << "\n";
}

}  // namespace shore::viewer
