#include "ui/gl_program.h"

#include <stdexcept>
#include <vector>

namespace lacet::ui {
namespace {

GLuint compile(const std::string& name, GLenum type, const char* source) {
    const GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &source, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint n = 0;
        glGetShaderiv(s, GL_INFO_LOG_LENGTH, &n);
        std::vector<char> log(std::size_t(std::max(n, 1)));
        glGetShaderInfoLog(s, n, nullptr, log.data());
        glDeleteShader(s);
        throw std::runtime_error(name + (type == GL_VERTEX_SHADER ? " vertex" : " fragment") + " shader: " + log.data());
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
        GLint n = 0;
        glGetProgramiv(id_, GL_INFO_LOG_LENGTH, &n);
        std::vector<char> log(std::size_t(std::max(n, 1)));
        glGetProgramInfoLog(id_, n, nullptr, log.data());
        glDeleteProgram(id_);
        id_ = 0;
        throw std::runtime_error(name + " program: " + log.data());
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
