// shore-bench viewer: the OpenGL renderer on Mesa's llvmpipe, headless (EGL): frame time at
// 1280 x 720 for the vehicle and the pond, triangles drawn against the full-resolution
// meshes, mesh bytes uploaded per frame (soil while the wheels drive, water) against a
// whole-field upload, chunks culled, and the time of one headless picture. Built when
// shore_render is (SHORE_BUILD_VIEWER finds libepoxy).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <vector>

#include <btBulletDynamicsCommon.h>

#include "shore/render/camera.h"
#include "shore/render/headless.h"
#include "shore/render/picture.h"
#include "shore/render/renderer.h"
#include "shore/scenes/runner.h"
#include "sweep.h"

namespace shore::bench {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

std::unique_ptr<scenes::Scene> make(const std::string& name, scenes::SceneOptions& options) {
  const scenes::SceneType& type = *scenes::find_scene(name);
  scenes::Overrides o;
  o.write_files = false;
  o.threads = 1;
  options = scenes::resolve(type, o);
  return type.create(options);
}

struct FrameFigures {
  double render_ms = 0, frame_ms = 0;
  double soil_bytes = 0, whole_soil_bytes = 0, water_bytes = 0, whole_water_bytes = 0;  // per frame (mean)
  double first_bytes = 0;                                        // the first frame's soil and water upload
  double surface_triangles = 0, full_triangles = 0, culled = 0;  // per frame (mean)
};

double mean(const std::vector<double>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0) / double(std::max<std::size_t>(v.size(), 1));
}

/// `frames` viewer frames of 1/60 s each at 1280 x 720, after `warmup` s simulated without
/// drawing (the vehicle reaches the sand): the substeps, then the draw (meshes brought up
/// to date, changed chunks uploaded; the renderer finishes each frame, so the time includes
/// the rasterizer's). The camera follows the scene's focus, as the viewer's does.
FrameFigures viewer_frames(render::Renderer& r, const std::string& name, int frames, double warmup) {
  scenes::SceneOptions o;
  auto scene = make(name, o);
  const scenes::SceneContents c = scene->contents();
  r.set_contents(c);
  render::OrbitCamera camera = render::OrbitCamera::framing(c.bounds);
  const render::RenderSettings settings = render::picture_settings(c);
  r.draw(camera, 1280, 720, settings);  // the whole field, once
  FrameFigures out;
  out.first_bytes = double(r.stats().soil_bytes + r.stats().water_bytes);
  for (int k = 0; k < static_cast<int>(std::lround(warmup / o.substep)); ++k) scene->step();
  r.draw(camera, 1280, 720, settings);  // what the warm-up changed
  const int per_frame = std::max(1, static_cast<int>(std::lround(1.0 / 60.0 / o.substep)));
  std::vector<double> render_ms, frame_ms, soil, water, tris, culled;
  for (int f = 0; f < frames; ++f) {
    const auto t0 = Clock::now();
    for (int k = 0; k < per_frame; ++k) scene->step();
    if (c.focus != nullptr) {
      const btVector3 p = c.focus->getWorldTransform().getOrigin();
      camera.target = {double(p.x()), double(p.y()), double(p.z())};
    }
    const auto t1 = Clock::now();
    r.draw(camera, 1280, 720, settings);
    render_ms.push_back(ms_since(t1));
    frame_ms.push_back(ms_since(t0));
    soil.push_back(double(r.stats().soil_bytes));
    water.push_back(double(r.stats().water_bytes));
    tris.push_back(double(r.stats().surface_triangles));
    culled.push_back(double(r.stats().chunks_culled));
  }
  out.render_ms = median(render_ms);
  out.frame_ms = median(frame_ms);
  out.soil_bytes = mean(soil);
  out.water_bytes = mean(water);
  out.whole_soil_bytes = double(r.stats().whole_soil_bytes);
  out.whole_water_bytes = double(r.stats().whole_water_bytes);
  out.surface_triangles = mean(tris);
  out.full_triangles = double(r.stats().full_triangles);
  out.culled = mean(culled);
  r.clear();
  return out;
}

void add_figures(SweepResult& out, const std::string& name, const FrameFigures& f) {
  const std::string p = "viewer." + name + "_";
  out.figure(p + "render_ms_per_frame", f.render_ms, "ms");
  out.figure(p + "frame_ms", f.frame_ms, "ms");
  out.figure(p + "surface_triangles", f.surface_triangles, "triangles");
  out.figure(p + "full_triangles", f.full_triangles, "triangles");
  if (f.full_triangles > 0) out.figure(p + "triangles_share", f.surface_triangles / f.full_triangles, "1");
  out.figure(p + "chunks_culled", f.culled, "chunks");
  if (f.whole_soil_bytes > 0) {
    out.figure(p + "soil_bytes_per_frame", f.soil_bytes, "B");
    out.figure(p + "whole_soil_bytes", f.whole_soil_bytes, "B");
    out.figure(p + "upload_share", f.soil_bytes / f.whole_soil_bytes, "1");
  }
  if (f.whole_water_bytes > 0) {
    out.figure(p + "water_bytes_per_frame", f.water_bytes, "B");
    out.figure(p + "whole_water_bytes", f.whole_water_bytes, "B");
    out.figure(p + "water_upload_share", f.water_bytes / f.whole_water_bytes, "1");
  }
}

void run(const SweepContext& ctx, SweepResult& out) {
  std::string gl;
  {
    render::HeadlessContext context;
    gl = context.description();
    render::Renderer renderer;
    const int frames = ctx.quick ? 20 : 90;
    Table& t =
        out.table("viewer_frames", {"scene", "render_ms_per_frame", "frame_ms", "surface_triangles", "full_triangles",
                                    "chunks_culled", "soil_bytes_per_frame", "whole_soil_bytes",
                                    "water_bytes_per_frame", "whole_water_bytes", "first_frame_bytes"});
    for (const char* name : {"vehicle", "pond"}) {
      ctx.progress(std::string(name) + ": " + std::to_string(frames) + " frames at 1280 x 720");
      // The vehicle starts 2 m before the sand at up to 2 m/s: 2 s brings its front wheels onto it.
      const FrameFigures f = viewer_frames(renderer, name, frames, std::string(name) == "vehicle" ? 2.0 : 0.5);
      t.add({std::string(name), f.render_ms, f.frame_ms, f.surface_triangles, f.full_triangles, f.culled, f.soil_bytes,
             f.whole_soil_bytes, f.water_bytes, f.whole_water_bytes, f.first_bytes});
      add_figures(out, name, f);
    }
  }  // the context goes before scene_picture makes its own
  // One headless picture of the vehicle scene at its start (its own context, as shore-demo makes it).
  ctx.progress("headless pictures");
  scenes::SceneOptions o;
  auto scene = make("vehicle", o);
  std::vector<double> ms;
  for (int k = 0; k < (ctx.quick ? 3 : 7); ++k) {
    const auto t0 = Clock::now();
    (void)render::scene_picture(*scene);
    ms.push_back(ms_since(t0));
  }
  out.figure("viewer.picture_first_ms", ms.front(), "ms");
  out.figure("viewer.picture_ms", median(std::vector<double>(ms.begin() + 1, ms.end())), "ms");
  out.note("viewer: " + gl +
           ", headless; a frame is 1/60 s of the scene (its substeps) then "
           "the renderer's draw at 1280 x 720 with 4x MSAA and a 2048^2 shadow map, the camera following the "
           "scene's focus; surfaces are shore::mesh chunks at 1 px: triangles drawn (after frustum culling) "
           "against two per cell, bytes are the changed chunks' vertices and indices uploaded per frame against "
           "uploading the full-resolution mesh (40 B per node, 12 B per triangle) once; the first picture "
           "includes the EGL context and shader compilation.");
}

const SweepRegistrar kRegistered{
    {.name = "viewer",
     .description = "OpenGL renderer on llvmpipe: frame time, soil upload, headless picture",
     .run = run}};

}  // namespace
}  // namespace shore::bench
