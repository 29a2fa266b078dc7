// shore-viewer in a window: GLFW 3, Dear ImGui panels, the renderer drawing the 3-D view.
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <epoxy/gl.h>
// GLFW after the loader's header; it must not include its own GL header.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include "panels.h"
#include "report.h"
#include "run.h"
#include "session.h"
#include "shore/scenes/image.h"

namespace shore::viewer {
namespace {

struct Mouse {
  double x = 0, y = 0;
  bool left = false, right = false, middle = false;
};

void handle_keys(GLFWwindow* w, Session& s) {
  if (ImGui::GetIO().WantCaptureKeyboard) return;
  auto down = [&](int k) { return glfwGetKey(w, k) == GLFW_PRESS; };
  s.forward = down(GLFW_KEY_UP) ? 1.0 : down(GLFW_KEY_DOWN) ? -1.0 : 0.0;
  s.turn = down(GLFW_KEY_LEFT) ? 1.0 : down(GLFW_KEY_RIGHT) ? -1.0 : 0.0;
}

void handle_mouse(GLFWwindow* w, Session& s, Mouse& m, int width, int height) {
  double x = 0, y = 0;
  glfwGetCursorPos(w, &x, &y);
  const bool left = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  const bool right = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  const bool middle = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
  if (!ImGui::GetIO().WantCaptureMouse) {
    const bool ctrl =
        glfwGetKey(w, GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS || glfwGetKey(w, GLFW_KEY_RIGHT_CONTROL) == GLFW_PRESS;
    if (left && !m.left && ctrl)
      s.click(s.drop_shape, x, y, width, height);
    else if (left && m.left && !ctrl)
      s.camera.orbit(x - m.x, y - m.y);
    if ((right && m.right) || (middle && m.middle)) {
      s.camera.pan(x - m.x, y - m.y, height);
      s.follow = false;
    }
  }
  m = {x, y, left, right, middle};
}

/// The window's back buffer (the 3-D view and the panels) as PNG.
void write_back_buffer(const std::filesystem::path& file, int w, int h) {
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  scenes::Image im(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::uint8_t* p = &rgba[(static_cast<std::size_t>(h - 1 - y) * static_cast<std::size_t>(w) + x) * 4];
      im.at(x, y) = {p[0], p[1], p[2]};
    }
  scenes::write_png(file, im);
}

double scroll_steps = 0.0;
void on_scroll(GLFWwindow*, double, double dy) { scroll_steps += dy; }

}  // namespace

int run_window(const RunOptions& o) {
  if (!glfwInit()) throw std::runtime_error("GLFW: cannot initialise (no display? try --headless)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  GLFWwindow* window = glfwCreateWindow(o.width, o.height, "shore-viewer", nullptr, nullptr);
  if (window == nullptr) {
    glfwTerminate();
    throw std::runtime_error("GLFW: cannot open an OpenGL 3.3 core window");
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(o.frames > 0 ? 0 : 1);
  glfwSetScrollCallback(window, on_scroll);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  int code = 0;
  {
    const std::unique_ptr<Session> started = start_session(o);
    Session& session = *started;
    Panels panels;
    RunReport report;
    Mouse mouse;
    for (int f = 0; !glfwWindowShouldClose(window) && (o.frames <= 0 || f < o.frames); ++f) {
      const auto t0 = std::chrono::steady_clock::now();
      glfwPollEvents();
      int w = 0, h = 0;
      glfwGetFramebufferSize(window, &w, &h);
      ImGui_ImplOpenGL3_NewFrame();
      ImGui_ImplGlfw_NewFrame();
      ImGui::NewFrame();
      if (o.script.empty()) {  // scripted runs take their input from the script alone
        handle_keys(window, session);
        handle_mouse(window, session, mouse, w, h);
        if (scroll_steps != 0.0 && !ImGui::GetIO().WantCaptureMouse) session.camera.zoom(scroll_steps);
        scroll_steps = 0.0;
      }
      session.advance();
      session.draw(w, h);
      session.renderer().present(w, h);
      panels.draw(session, w, h);
      ImGui::Render();
      glViewport(0, 0, w, h);
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
      const bool last = o.frames > 0 && f + 1 == o.frames;
      if (last && !o.window_shot.empty()) write_back_buffer(o.window_shot, w, h);
      glfwSwapBuffers(window);
      report.frame(session, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    int w = 0, h = 0;
    glfwGetFramebufferSize(window, &w, &h);
    finish_run(session, report, o, w, h);
    std::printf("shore-viewer: %s, %d frames\n", o.scene.c_str(), session.frame());
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  return code;
}

}  // namespace shore::viewer
