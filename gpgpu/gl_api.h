#pragma once
/// \file gl_api.h
/// The GL entry points nurbsgl uses, as a table of function pointers loaded from the current
/// context's get-proc-address (eglGetProcAddress, OSMesaGetProcAddress, glfwGetProcAddress).
///
/// Why not libepoxy for GL calls: epoxy decides between GLX and EGL at call time and aborts under
/// an OSMesa context ("Couldn't find current GLX or EGL context"); Mesa's libOSMesa exports its own
/// gl* symbols. Loading one table per context through the backend's own loader makes the same query
/// code run under every backend. Call sites read `gl::CreateTextures(...)`.
#include <GL/glcorearb.h>

#include <string>

namespace gpgpu::gl {

// clang-format off
// X(return type, name without the "gl" prefix, parameter list)
#define NURBSGL_GL_FUNCTIONS(X)                                                                       \
  X(const GLubyte*, GetString, (GLenum))                                                             \
  X(const GLubyte*, GetStringi, (GLenum, GLuint))                                                    \
  X(void, GetIntegerv, (GLenum, GLint*))                                                             \
  X(GLenum, GetError, ())                                                                            \
  X(void, Enable, (GLenum))                                                                          \
  X(void, Disable, (GLenum))                                                                         \
  X(void, Viewport, (GLint, GLint, GLsizei, GLsizei))                                                \
  X(void, Finish, ())                                                                                \
  X(void, Flush, ())                                                                                 \
  X(void, PixelStorei, (GLenum, GLint))                                                              \
  X(void, ColorMaski, (GLuint, GLboolean, GLboolean, GLboolean, GLboolean))                          \
  X(void, CreateTextures, (GLenum, GLsizei, GLuint*))                                                \
  X(void, DeleteTextures, (GLsizei, const GLuint*))                                                  \
  X(void, TextureStorage2D, (GLuint, GLsizei, GLenum, GLsizei, GLsizei))                             \
  X(void, TextureSubImage2D, (GLuint, GLint, GLint, GLint, GLsizei, GLsizei, GLenum, GLenum, const void*)) \
  X(void, TextureParameteri, (GLuint, GLenum, GLint))                                                \
  X(void, GetTextureSubImage,                                                                        \
    (GLuint, GLint, GLint, GLint, GLint, GLsizei, GLsizei, GLsizei, GLenum, GLenum, GLsizei, void*)) \
  X(void, BindTextureUnit, (GLuint, GLuint))                                                         \
  X(void, GenTextures, (GLsizei, GLuint*))                                                           \
  X(void, CreateFramebuffers, (GLsizei, GLuint*))                                                    \
  X(void, DeleteFramebuffers, (GLsizei, const GLuint*))                                              \
  X(void, BindFramebuffer, (GLenum, GLuint))                                                         \
  X(void, NamedFramebufferTexture, (GLuint, GLenum, GLuint, GLint))                                  \
  X(void, NamedFramebufferDrawBuffers, (GLuint, GLsizei, const GLenum*))                             \
  X(GLenum, CheckNamedFramebufferStatus, (GLuint, GLenum))                                           \
  X(GLuint, CreateShader, (GLenum))                                                                  \
  X(void, DeleteShader, (GLuint))                                                                    \
  X(void, ShaderSource, (GLuint, GLsizei, const GLchar* const*, const GLint*))                       \
  X(void, CompileShader, (GLuint))                                                                   \
  X(void, GetShaderiv, (GLuint, GLenum, GLint*))                                                     \
  X(void, GetShaderInfoLog, (GLuint, GLsizei, GLsizei*, GLchar*))                                    \
  X(GLuint, CreateProgram, ())                                                                       \
  X(void, DeleteProgram, (GLuint))                                                                   \
  X(void, AttachShader, (GLuint, GLuint))                                                            \
  X(void, LinkProgram, (GLuint))                                                                     \
  X(void, GetProgramiv, (GLuint, GLenum, GLint*))                                                    \
  X(void, GetProgramInfoLog, (GLuint, GLsizei, GLsizei*, GLchar*))                                   \
  X(void, UseProgram, (GLuint))                                                                      \
  X(GLint, GetUniformLocation, (GLuint, const GLchar*))                                              \
  X(void, ProgramUniform1i, (GLuint, GLint, GLint))                                                  \
  X(void, ProgramUniform1iv, (GLuint, GLint, GLsizei, const GLint*))                                 \
  X(void, ProgramUniform2i, (GLuint, GLint, GLint, GLint))                                           \
  X(void, ProgramUniform2iv, (GLuint, GLint, GLsizei, const GLint*))                                 \
  X(void, ProgramUniform4i, (GLuint, GLint, GLint, GLint, GLint, GLint))                             \
  X(void, ProgramUniform1ui, (GLuint, GLint, GLuint))                                                \
  X(void, ProgramUniform1f, (GLuint, GLint, GLfloat))                                                \
  X(void, ProgramUniform2f, (GLuint, GLint, GLfloat, GLfloat))                                       \
  X(void, ProgramUniform3f, (GLuint, GLint, GLfloat, GLfloat, GLfloat))                              \
  X(void, ProgramUniform4f, (GLuint, GLint, GLfloat, GLfloat, GLfloat, GLfloat))                     \
  X(void, ProgramUniformMatrix4fv, (GLuint, GLint, GLsizei, GLboolean, const GLfloat*))              \
  X(void, CreateVertexArrays, (GLsizei, GLuint*))                                                    \
  X(void, DeleteVertexArrays, (GLsizei, const GLuint*))                                              \
  X(void, BindVertexArray, (GLuint))                                                                 \
  X(void, DrawArrays, (GLenum, GLint, GLsizei))                                                      \
  X(void, CreateQueries, (GLenum, GLsizei, GLuint*))                                                 \
  X(void, DeleteQueries, (GLsizei, const GLuint*))                                                   \
  X(void, BeginQuery, (GLenum, GLuint))                                                              \
  X(void, EndQuery, (GLenum))                                                                        \
  X(void, GetQueryObjectui64v, (GLuint, GLenum, GLuint64*))                                          \
  X(void, GetQueryObjectiv, (GLuint, GLenum, GLint*))                                             \
  X(void, CreateBuffers, (GLsizei, GLuint*))                                                        \
  X(void, DeleteBuffers, (GLsizei, const GLuint*))                                                   \
  X(void, NamedBufferData, (GLuint, GLsizeiptr, const void*, GLenum))                                \
  X(void, VertexArrayVertexBuffer, (GLuint, GLuint, GLuint, GLintptr, GLsizei))                      \
  X(void, VertexArrayAttribFormat, (GLuint, GLuint, GLint, GLenum, GLboolean, GLuint))               \
  X(void, VertexArrayAttribBinding, (GLuint, GLuint, GLuint))                                        \
  X(void, EnableVertexArrayAttrib, (GLuint, GLuint))                                                 \
  X(void, StencilFunc, (GLenum, GLint, GLuint))                                                      \
  X(void, StencilOp, (GLenum, GLenum, GLenum))                                                       \
  X(void, StencilMask, (GLuint))                                                                     \
  X(void, ClearNamedFramebufferiv, (GLuint, GLenum, GLint, const GLint*))                            \
  X(void, CreateRenderbuffers, (GLsizei, GLuint*))                                                   \
  X(void, DeleteRenderbuffers, (GLsizei, const GLuint*))                                             \
  X(void, NamedRenderbufferStorage, (GLuint, GLenum, GLsizei, GLsizei))                              \
  X(void, NamedFramebufferRenderbuffer, (GLuint, GLenum, GLenum, GLuint))                            \
  X(void, GetQueryiv, (GLenum, GLenum, GLint*))                                                     \
  X(void, ClearNamedFramebufferfv, (GLuint, GLenum, GLint, const GLfloat*))                         \
  X(void, DebugMessageCallback, (GLDEBUGPROC, const void*))                                          \
  X(void, DebugMessageControl, (GLenum, GLenum, GLenum, GLsizei, const GLuint*, GLboolean))

// clang-format on
#define NURBSGL_DECLARE_GL(ret, name, params) \
  using name##_t = ret(APIENTRYP) params;     \
  extern name##_t name;
NURBSGL_GL_FUNCTIONS(NURBSGL_DECLARE_GL)
#undef NURBSGL_DECLARE_GL

/// A backend's loader: GL function name ("glCreateTextures") -> address, or nullptr.
using GetProcAddress = void* (*)(const char* name);

/// Loads every entry point of the table through `get_proc`. Throws std::runtime_error naming the
/// first missing function (a GL older than 4.5 core, or a broken driver).
void load(GetProcAddress get_proc);

/// Throws std::runtime_error("GL error GL_INVALID_OPERATION after <where>") if glGetError reports
/// one, or if KHR_debug output (gl_debug.h) has received a high-severity message since the last
/// check; the driver's messages are appended. Drains the whole error queue so later checks start clean.
void check_error(const char* where);

/// Name of a GL enum for messages ("GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT"), or its hex value.
std::string enum_name(GLenum value);

}  // namespace gpgpu::gl
