#pragma once
// Small owners of OpenGL objects and the shader compile step (a GL 3.3 core context must
// be current).

#include <string>
#include <utility>

#include <epoxy/gl.h>

namespace shore::render::gl {

/// Throws std::runtime_error naming `what` and the GL error if glGetError reports one.
void check(const char* what);

/// A linked program from vertex and fragment source (GLSL 330 core; the "#version" line is
/// added). Throws std::runtime_error with the compiler's log.
GLuint program(const std::string& vertex, const std::string& fragment, const char* name);

/// Owns one GL name; deleter is a function such as glDeleteBuffers taking (count, names).
template <void (*Delete)(GLsizei, const GLuint*)>
class Name {
 public:
  Name() = default;
  explicit Name(GLuint id) : id_(id) {}
  ~Name() { reset(); }
  Name(Name&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  Name& operator=(Name&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  Name(const Name&) = delete;
  Name& operator=(const Name&) = delete;
  void reset() {
    if (id_ != 0) Delete(1, &id_);
    id_ = 0;
  }
  [[nodiscard]] GLuint get() const noexcept { return id_; }

 private:
  GLuint id_ = 0;
};

inline void delete_buffers(GLsizei n, const GLuint* p) { glDeleteBuffers(n, p); }
inline void delete_vertex_arrays(GLsizei n, const GLuint* p) { glDeleteVertexArrays(n, p); }
inline void delete_textures(GLsizei n, const GLuint* p) { glDeleteTextures(n, p); }
inline void delete_framebuffers(GLsizei n, const GLuint* p) { glDeleteFramebuffers(n, p); }
inline void delete_renderbuffers(GLsizei n, const GLuint* p) { glDeleteRenderbuffers(n, p); }
inline void delete_program(GLsizei, const GLuint* p) { glDeleteProgram(*p); }

using Buffer = Name<delete_buffers>;
using VertexArray = Name<delete_vertex_arrays>;
using Texture = Name<delete_textures>;
using Framebuffer = Name<delete_framebuffers>;
using Renderbuffer = Name<delete_renderbuffers>;
using Program = Name<delete_program>;

/// A new GL name made by a glGen* function (count, names), owned.
template <class Owner, void (*Generate)(GLsizei, GLuint*)>
Owner make() {
  GLuint id = 0;
  Generate(1, &id);
  return Owner(id);
}
inline void gen_buffers(GLsizei n, GLuint* p) { glGenBuffers(n, p); }
inline void gen_vertex_arrays(GLsizei n, GLuint* p) { glGenVertexArrays(n, p); }
inline void gen_textures(GLsizei n, GLuint* p) { glGenTextures(n, p); }
inline void gen_framebuffers(GLsizei n, GLuint* p) { glGenFramebuffers(n, p); }
inline void gen_renderbuffers(GLsizei n, GLuint* p) { glGenRenderbuffers(n, p); }
inline Buffer make_buffer() { return make<Buffer, gen_buffers>(); }
inline VertexArray make_vertex_array() { return make<VertexArray, gen_vertex_arrays>(); }
inline Texture make_texture() { return make<Texture, gen_textures>(); }
inline Framebuffer make_framebuffer() { return make<Framebuffer, gen_framebuffers>(); }
inline Renderbuffer make_renderbuffer() { return make<Renderbuffer, gen_renderbuffers>(); }

}  // namespace shore::render::gl
