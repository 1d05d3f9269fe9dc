#pragma once
/// \file gl_debug.h
/// KHR_debug output (core since GL 4.3): the driver's own account of a mistake ("glBindTextureUnit
/// (non-gen name)") instead of a bare GL_INVALID_OPERATION found later. On in builds without NDEBUG,
/// or when NURBSGL_GL_DEBUG=1 (=0 turns it off). Messages of high and medium severity are printed
/// on stderr as they arrive; high-severity ones (but the shader compiler's: ShaderError carries
/// those) are also kept until the next gl::check_error, which throws with them (throwing from the
/// callback itself would unwind through the driver).
#include <string>

namespace gpgpu::gl {

/// NURBSGL_GL_DEBUG when set ("0" = off, anything else = on), else on iff NDEBUG is not defined.
[[nodiscard]] bool debug_output_requested();

/// Installs the message callback on the current context, synchronous (the message arrives inside
/// the offending call), low-severity messages and notifications filtered out. Needs the gl:: table.
void enable_debug_output();

/// The high-severity messages received since the last call, joined by "; " (empty when none).
[[nodiscard]] std::string take_debug_errors();

}  // namespace gpgpu::gl
