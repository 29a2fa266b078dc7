#include "shore/scenes/soil_sync.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>

#include "shore/core/error.h"
#include "shore/scenes/contents.h"
#include "shore/scenes/runner.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

struct Link {  // one soil, its replica and where each stands
  terrain::Terrain* server = nullptr;
  std::unique_ptr<terrain::Terrain> replica;
  std::uint64_t sent = 0, mirrored = 0;
};

/// Largest |server - replica| of heights and sinkages over the bounds.
double largest_error(const Link& l, const Bounds& b) {
  const terrain::Terrain& s = *l.server;
  double worst = 0.0;
  for (std::int64_t j = s.column_j(b.y0); j <= s.column_j(b.y1); ++j)
    for (std::int64_t i = s.column_i(b.x0); i <= s.column_i(b.x1); ++i)
      worst = std::max({worst, std::fabs(s.height(i, j) - l.replica->height(i, j)),
                        std::fabs(s.sinkage(i, j) - l.replica->sinkage(i, j))});
  return worst;
}

void sync_once(Link& l, const terrain::DeltaSettings& settings, SyncResult& r) {
  terrain::DeltaStats st;
  auto start = Clock::now();
  const std::vector<unsigned char> delta = terrain::SoilDelta::encode(*l.server, l.sent, settings, &st);
  r.encode_seconds += seconds_since(start);
  l.sent = l.server->generation();
  start = Clock::now();
  l.mirrored = terrain::SoilDelta::apply(*l.replica, delta, l.mirrored);
  r.decode_seconds += seconds_since(start);
  r.delta_bytes += static_cast<double>(st.bytes), r.changed_columns += static_cast<double>(st.columns);
}

}  // namespace

SyncResult sync_scene(const std::string& name, double seconds, const terrain::DeltaSettings& settings) {
  const SceneType* type = find_scene(name);
  if (type == nullptr) throw InvalidSetting("scenes.sync_scene(scene)", name, "must name a scene");
  Overrides o;
  o.threads = 1;
  o.seconds = seconds;
  o.write_files = false;
  const SceneOptions opt = resolve(*type, o);
  const std::unique_ptr<Scene> scene = type->create(opt);
  const SceneContents contents = scene->contents();
  if (contents.soils.empty()) throw InvalidSetting("scenes.sync_scene(scene)", name, "must have soil");
  std::vector<Link> links;
  for (const SoilContents& s : contents.soils) {
    Link l;
    l.server = s.soil;
    l.replica = std::make_unique<terrain::Terrain>(s.soil->settings());
    // The replica starts as the untouched soil; the first delta is a snapshot (from
    // generation 0), so it also brings the palette and map a scene painted when it was made.
    l.sent = l.mirrored = 0;
    links.push_back(std::move(l));
  }
  SyncResult r;
  r.soils = static_cast<int>(links.size());
  const int per_sync = std::max(1, static_cast<int>(std::lround(1.0 / (20.0 * opt.substep))));
  for (int k = 1; k <= opt.substeps(); ++k) {
    scene->step();
    if (k % per_sync != 0) continue;
    ++r.syncs;
    for (Link& l : links) sync_once(l, settings, r);
  }
  r.same_soil_hash = true;
  for (const Link& l : links) {
    r.max_error = std::max(r.max_error, largest_error(l, contents.bounds));
    r.same_soil_hash = r.same_soil_hash && l.server->state_hash() == l.replica->state_hash();
  }
  r.sim_seconds = opt.substeps() * opt.substep;
  return r;
}

}  // namespace shore::scenes
