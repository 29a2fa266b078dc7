#include "gl_util.h"

#include <stdexcept>
#include <vector>

namespace shore::render::gl {

void check(const char* what) {
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR) throw std::runtime_error(std::string("OpenGL error ") + std::to_string(e) + " in " + what);
}

namespace {
/// The compile or link log of a shader or program.
template <void (*Get)(GLuint, GLenum, GLint*), void (*Log)(GLuint, GLsizei, GLsizei*, GLchar*)>
std::string info_log(GLuint object) {
  GLint n = 0;
  Get(object, GL_INFO_LOG_LENGTH, &n);
  std::vector<char> log(static_cast<std::size_t>(n) + 1, '\0');
  Log(object, n, nullptr, log.data());
  return log.data();
}
void shader_iv(GLuint s, GLenum p, GLint* v) { glGetShaderiv(s, p, v); }
void shader_log(GLuint s, GLsizei n, GLsizei* l, GLchar* t) { glGetShaderInfoLog(s, n, l, t); }
void program_iv(GLuint s, GLenum p, GLint* v) { glGetProgramiv(s, p, v); }
void program_log(GLuint s, GLsizei n, GLsizei* l, GLchar* t) { glGetProgramInfoLog(s, n, l, t); }

GLuint compile(GLenum type, const std::string& body, const char* name) {
  const std::string source = "#version 330 core\n" + body;
  const GLuint s = glCreateShader(type);
  const char* text = source.c_str();
  glShaderSource(s, 1, &text, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = info_log<shader_iv, shader_log>(s);
    glDeleteShader(s);
    throw std::runtime_error(std::string("shader ") + name + (type == GL_VERTEX_SHADER ? " (vertex)" : " (fragment)") +
                             ": " + log);
  }
  return s;
}
}  // namespace

GLuint program(const std::string& vertex, const std::string& fragment, const char* name) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex, name);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment, name);
  const GLuint p = glCreateProgram();
  glAttachShader(p, vs);
  glAttachShader(p, fs);
  glLinkProgram(p);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = info_log<program_iv, program_log>(p);
    glDeleteProgram(p);
    throw std::runtime_error(std::string("program ") + name + ": " + log);
  }
  return p;
}

}  // namespace shore::render::gl
