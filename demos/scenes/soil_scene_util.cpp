#include "soil_scene_util.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "shore/bullet/envelope.h"

namespace shore::demo::soil_scene {

namespace {

void hash_vector(StateHash& h, const btVector3& v) {
  for (int a = 0; a < 3; ++a) h.add(static_cast<double>(v[a]));
}

long non_finite(const btVector3& v) {
  long n = 0;
  for (int a = 0; a < 3; ++a) n += std::isfinite(v[a]) ? 0 : 1;
  return n;
}

}  // namespace

HeightGrid grid_over(double x0, double y0, double x1, double y1, double cell) {
  const auto i0 = static_cast<std::int64_t>(std::floor(x0 / cell));
  const auto j0 = static_cast<std::int64_t>(std::floor(y0 / cell));
  const auto i1 = static_cast<std::int64_t>(std::ceil(x1 / cell));
  const auto j1 = static_cast<std::int64_t>(std::ceil(y1 / cell));
  return HeightGrid(static_cast<int>(i1 - i0 + 1), static_cast<int>(j1 - j0 + 1), cell, static_cast<double>(i0) * cell,
                    static_cast<double>(j0) * cell);
}

HeightGrid sample(const std::vector<Patch>& patches, const HeightGrid& frame, Field field, double outside) {
  HeightGrid g = frame;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double x = g.x(i), y = g.y(j);
      double v = outside;
      for (const Patch& p : patches) {
        if (!p.region.contains(x, y)) continue;
        const std::int64_t ci = p.soil->column_i(x), cj = p.soil->column_j(y);
        v = field == Field::height ? p.soil->height(ci, cj)
            : field == Field::base ? p.soil->base_height(ci, cj)
                                   : p.soil->sinkage(ci, cj);
        break;
      }
      g.at(i, j) = v;
    }
  return g;
}

BodyEnvelopes body_envelopes(const std::vector<const btCollisionObject*>& bodies, const HeightGrid& frame) {
  bullet::EnvelopeGrid grid;
  grid.origin_x = frame.x0;
  grid.origin_y = frame.y0;
  grid.cell = frame.cell;
  bullet::EnvelopeOptions options;
  options.upper = true;
  options.include_margin = false;
  bullet::EnvelopeRasterizer rasterizer(grid, options);
  EnvelopeRaster raster;
  raster.resize(0, 0, frame.nx, frame.ny, true);
  for (const btCollisionObject* b : bodies)
    rasterizer.accumulate(*b->getCollisionShape(), b->getWorldTransform(), raster);
  BodyEnvelopes out{frame, frame};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int j = 0; j < frame.ny; ++j)
    for (int i = 0; i < frame.nx; ++i) {
      const std::size_t k = raster.index(i, j);
      const bool covered = raster.covers(k);
      out.top.at(i, j) = covered ? raster.upper[k] : nan;
      out.bottom.at(i, j) = covered ? raster.lower[k] : nan;
    }
  return out;
}

double volume_drift_rel(const terrain::Terrain& soil) {
  const terrain::VolumeTotals v = soil.volume();
  const double drift = std::abs(v.total() - v.edited);
  const double moved = v.compacted + std::abs(v.ground);
  return drift / (moved > 0.0 ? moved : 1e-12);
}

double max_lowering(const HeightGrid& baseline, const HeightGrid& heights) {
  double m = 0.0;
  for (std::size_t k = 0; k < heights.z.size() && k < baseline.z.size(); ++k)
    if (std::isfinite(heights.z[k]) && std::isfinite(baseline.z[k])) m = std::max(m, baseline.z[k] - heights.z[k]);
  return m;
}

double max_of(const HeightGrid& g) {
  double m = 0.0;
  bool any = false;
  for (double v : g.z)
    if (std::isfinite(v)) {
      m = any ? std::max(m, v) : v;
      any = true;
    }
  return m;
}

void hash_bodies(StateHash& hash, const std::vector<const btRigidBody*>& bodies) {
  for (const btRigidBody* b : bodies) {
    const btTransform& t = b->getWorldTransform();
    hash_vector(hash, t.getOrigin());
    for (int r = 0; r < 3; ++r) hash_vector(hash, t.getBasis()[r]);
    hash_vector(hash, b->getLinearVelocity());
    hash_vector(hash, b->getAngularVelocity());
  }
}

long non_finite_bodies(const std::vector<const btRigidBody*>& bodies) {
  long n = 0;
  for (const btRigidBody* b : bodies) {
    const btTransform& t = b->getWorldTransform();
    n += non_finite(t.getOrigin()) + non_finite(b->getLinearVelocity()) + non_finite(b->getAngularVelocity());
    for (int r = 0; r < 3; ++r) n += non_finite(t.getBasis()[r]);
  }
  return n;
}

Image oblique_frame(const HeightGrid& heights, const HeightGrid& baseline, const BodyEnvelopes* bodies,
                    double exaggeration, int min_pixels, const std::string& title, double deformation_scale,
                    double elevation_deg, bool legend) {
  ReliefStyle style;
  style.baseline = &baseline;
  style.deformation_scale = deformation_scale;
  if (bodies != nullptr) {
    style.bodies = &bodies->top;
    style.body_bottoms = &bodies->bottom;
  }
  style.exaggeration = exaggeration;
  style.min_pixels = min_pixels;
  style.title = title;
  style.legend = legend;
  return render_oblique(heights, style, elevation_deg);
}

std::string time_label(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "t = %.2f s", t);
  return buf;
}

void FilmSchedule::capture_soil(int k, double t, const std::vector<Patch>& patches, const HeightGrid& frame,
                                const HeightGrid& baseline, const std::vector<const btCollisionObject*>& bodies,
                                int min_pixels) {
  if (!due(k)) return;
  const BodyEnvelopes env = body_envelopes(bodies, frame);
  add(oblique_frame(sample(patches, frame, Field::height), baseline, &env, 2.0, min_pixels, ""), t);
}

double tilt_from_vertical(const btRigidBody& body, int axis) {
  const btVector3 a = body.getWorldTransform().getBasis().getColumn(axis);
  return std::acos(std::clamp(static_cast<double>(a.z()), -1.0, 1.0));
}

}  // namespace shore::demo::soil_scene
