#pragma once
// An OpenGL 3.3 core context without a window or a display: EGL on Mesa's surfaceless
// platform (llvmpipe when there is no GPU), falling back to EGL's default display. The
// renderer draws into its own framebuffers, so no surface is needed.

#include <stdexcept>
#include <string>

namespace shore::render {

/// No OpenGL 3.3 core context could be made; the message says which step failed.
class ContextError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class HeadlessContext {
 public:
  /// Creates the context and makes it current on this thread. Throws ContextError.
  HeadlessContext();
  ~HeadlessContext();
  HeadlessContext(const HeadlessContext&) = delete;
  HeadlessContext& operator=(const HeadlessContext&) = delete;

  /// Makes the context current on this thread again.
  void make_current();
  /// "OpenGL 4.5 (Core Profile) Mesa ... | llvmpipe ...".
  [[nodiscard]] std::string description() const;

 private:
  void* display_ = nullptr;
  void* context_ = nullptr;
};

}  // namespace shore::render
