// shore-viewer --headless: the same session and renderer without a window (EGL on Mesa).
#include <chrono>
#include <cstdio>

#include "report.h"
#include "run.h"
#include "session.h"
#include "shore/render/headless.h"

namespace shore::viewer {

int run_headless(const RunOptions& o) {
  render::HeadlessContext context;
  const std::unique_ptr<Session> started = start_session(o);
  Session& session = *started;
  RunReport report;
  const int frames = o.frames > 0 ? o.frames : 1;
  for (int f = 0; f < frames; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    session.advance();
    session.draw(o.width, o.height);
    report.frame(session, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  finish_run(session, report, o, o.width, o.height);
  std::printf("shore-viewer: %s, %d frames headless (%s)\n", o.scene.c_str(), frames, context.description().c_str());
  return 0;
}

}  // namespace shore::viewer
