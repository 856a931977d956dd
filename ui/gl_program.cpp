#include "ui/gl_program.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace lacet::ui {
namespace {

// The info log of a shader or program (getLength, getLog: glGetShaderiv/glGetShaderInfoLog or the
// program pair).
template <class GetLength, class GetLog>
std::string infoLog(GLuint id, GetLength getLength, GetLog getLog) {
    GLint n = 0;
    getLength(id, GL_INFO_LOG_LENGTH, &n);
    std::vector<char> log(std::size_t(std::max(n, 1)));
    getLog(id, n, nullptr, log.data());
    return log.data();
}

GLuint compile(const std::string& name, GLenum type, const char* source) {
    const GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &source, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        const std::string log = infoLog(s, glGetShaderiv, glGetShaderInfoLog);
        glDeleteShader(s);
        throw std::runtime_error(name + (type == GL_VERTEX_SHADER ? " vertex" : " fragment") + " shader: " + log);
    }
    return s;
}

}  // namespace

GlProgram::GlProgram(const std::string& name, const char* vertexSource, const char* fragmentSource) {
    const GLuint vs = compile(name, GL_VERTEX_SHADER, vertexSource);
    const GLuint fs = compile(name, GL_FRAGMENT_SHADER, fragmentSource);
    id_ = glCreateProgram();
    glAttachShader(id_, vs);
    glAttachShader(id_, fs);
    glLinkProgram(id_);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (!ok) {
        const std::string log = infoLog(id_, glGetProgramiv, glGetProgramInfoLog);
        glDeleteProgram(id_);
        id_ = 0;
        throw std::runtime_error(name + " program: " + log);
    }
}

GlProgram& GlProgram::operator=(GlProgram&& o) noexcept {
    if (this != &o) {
        if (id_) glDeleteProgram(id_);
        id_ = o.id_;
        o.id_ = 0;
    }
    return *this;
}

GlProgram::~GlProgram() {
    if (id_) glDeleteProgram(id_);
}

}  // namespace lacet::ui
