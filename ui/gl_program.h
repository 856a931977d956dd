#pragma once
// A linked OpenGL program from vertex and fragment sources (GLSL 410 core); throws
// std::runtime_error with the compiler's log naming the shader.

#include <string>

#include <epoxy/gl.h>

namespace lacet::ui {

class GlProgram {
public:
    GlProgram() = default;
    GlProgram(const std::string& name, const char* vertexSource, const char* fragmentSource);
    GlProgram(const GlProgram&) = delete;
    GlProgram& operator=(const GlProgram&) = delete;
    GlProgram(GlProgram&& o) noexcept : id_(o.id_) { o.id_ = 0; }
    GlProgram& operator=(GlProgram&& o) noexcept;
    ~GlProgram();

    GLuint id() const { return id_; }
    GLint uniform(const char* name) const { return glGetUniformLocation(id_, name); }

private:
    GLuint id_ = 0;
};

}  // namespace lacet::ui
