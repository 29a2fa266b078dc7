#include "gl_util.h"

#include <stdexcept>
#include <vector>

namespace shore::render::gl {

void check(const char* what) {
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR) throw std::runtime_error(std::string("OpenGL error ") + std::to_string(e) + " in " + what);
}

namespace {
GLuint compile(GLenum type, const std::string& body, const char* name) {
  const std::string source = "#version 330 core\n" + body;
  const GLuint s = glCreateShader(type);
  const char* text = source.c_str();
  glShaderSource(s, 1, &text, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint n = 0;
    glGetShaderiv(s, GL_INFO_LOG_LENGTH, &n);
    std::vector<char> log(static_cast<std::size_t>(n) + 1, '\0');
    glGetShaderInfoLog(s, n, nullptr, log.data());
    glDeleteShader(s);
    throw std::runtime_error(std::string("shader ") + name + (type == GL_VERTEX_SHADER ? " (vertex)" : " (fragment)") +
                             ": " + log.data());
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
    GLint n = 0;
    glGetProgramiv(p, GL_INFO_LOG_LENGTH, &n);
    std::vector<char> log(static_cast<std::size_t>(n) + 1, '\0');
    glGetProgramInfoLog(p, n, nullptr, log.data());
    glDeleteProgram(p);
    throw std::runtime_error(std::string("program ") + name + ": " + log.data());
  }
  return p;
}

}  // namespace shore::render::gl
