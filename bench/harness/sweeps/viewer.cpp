// shore-bench viewer: the OpenGL renderer on Mesa's llvmpipe, headless (EGL): frame time at
// 1280 x 720 for the vehicle and the pond, soil bytes uploaded per frame while the wheels
// drive against a whole-field upload, and the time of one headless picture. Built when
// shore_render is (SHORE_BUILD_VIEWER finds libepoxy).
#include <algorithm>
#include <chrono>
#include <memory>
#include <numeric>
#include <vector>

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
  double render_ms = 0, frame_ms = 0, bytes_per_frame = 0, whole_bytes = 0;
};

/// `frames` viewer frames of 1/60 s each at 1280 x 720, after `warmup` s simulated without
/// drawing (the vehicle reaches the sand): the substeps, then sync and draw (the renderer
/// finishes each frame, so the time includes the rasterizer's).
FrameFigures viewer_frames(render::Renderer& r, const std::string& name, int frames, double warmup) {
  scenes::SceneOptions o;
  auto scene = make(name, o);
  const scenes::SceneContents c = scene->contents();
  r.set_contents(c);
  r.sync();  // the whole field, once
  for (int k = 0; k < static_cast<int>(std::lround(warmup / o.substep)); ++k) scene->step();
  r.sync();  // what the warm-up changed
  render::OrbitCamera camera = render::OrbitCamera::framing(c.bounds);
  const render::RenderSettings settings = render::picture_settings(c);
  const int per_frame = std::max(1, static_cast<int>(std::lround(1.0 / 60.0 / o.substep)));
  std::vector<double> render_ms, frame_ms, bytes;
  for (int f = 0; f < frames; ++f) {
    const auto t0 = Clock::now();
    for (int k = 0; k < per_frame; ++k) scene->step();
    const auto t1 = Clock::now();
    r.sync();
    r.draw(camera, 1280, 720, settings);
    render_ms.push_back(ms_since(t1));
    frame_ms.push_back(ms_since(t0));
    bytes.push_back(double(r.stats().soil_bytes));
  }
  FrameFigures out{median(render_ms), median(frame_ms),
                   std::accumulate(bytes.begin(), bytes.end(), 0.0) / std::max<std::size_t>(bytes.size(), 1),
                   double(r.stats().whole_soil_bytes)};
  r.clear();
  return out;
}

void run(const SweepContext& ctx, SweepResult& out) {
  std::string gl;
  {
    render::HeadlessContext context;
    gl = context.description();
    render::Renderer renderer;
    const int frames = ctx.quick ? 20 : 90;
    Table& t = out.table("viewer_frames",
                         {"scene", "render_ms_per_frame", "frame_ms", "soil_bytes_per_frame", "whole_soil_bytes"});
    for (const char* name : {"vehicle", "pond"}) {
      ctx.progress(std::string(name) + ": " + std::to_string(frames) + " frames at 1280 x 720");
      // The vehicle starts 2 m before the sand at up to 2 m/s: 2 s brings its front wheels onto it.
      const FrameFigures f = viewer_frames(renderer, name, frames, std::string(name) == "vehicle" ? 2.0 : 0.5);
      t.add({std::string(name), f.render_ms, f.frame_ms, f.bytes_per_frame, f.whole_bytes});
      out.figure(std::string("viewer.") + name + "_render_ms_per_frame", f.render_ms, "ms");
      out.figure(std::string("viewer.") + name + "_frame_ms", f.frame_ms, "ms");
      if (f.whole_bytes > 0) {
        out.figure(std::string("viewer.") + name + "_soil_bytes_per_frame", f.bytes_per_frame, "B");
        out.figure(std::string("viewer.") + name + "_whole_soil_bytes", f.whole_bytes, "B");
        out.figure(std::string("viewer.") + name + "_upload_share", f.bytes_per_frame / f.whole_bytes, "1");
      }
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
           "the renderer's sync and draw at 1280 x 720 with 4x MSAA and a 2048^2 shadow map; soil bytes are "
           "what the changed-column uploads sent, against uploading every drawn column; the first picture "
           "includes the EGL context and shader compilation.");
}

const SweepRegistrar kRegistered{
    {.name = "viewer",
     .description = "OpenGL renderer on llvmpipe: frame time, soil upload, headless picture",
     .run = run}};

}  // namespace
}  // namespace shore::bench
