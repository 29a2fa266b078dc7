#include "run.h"

#include "report.h"
#include "session.h"

namespace shore::viewer {

std::unique_ptr<Session> start_session(const RunOptions& o) {
  auto session = std::make_unique<Session>(o.scene, o.smoke);
  session->attach_renderer();
  session->settings.shadows = o.shadows;
  session->settings.samples = o.samples;
  if (!o.script.empty()) session->set_script(read_script(o.script));
  return session;
}

void finish_run(const Session& session, const RunReport& report, const RunOptions& o, int width, int height) {
  if (!o.screenshot.empty()) session.screenshot(o.screenshot);
  if (!o.report.empty()) report.write(o.report, session, width, height);
}

}  // namespace shore::viewer
