#pragma once
/// \file uniform_names.h
/// The uniform names a GLSL source declares, read from the text. GL only knows the *active*
/// uniforms: one the compiler optimised away (unused under some #define) has no location, exactly
/// like a misspelt name. Program keeps this set to tell the two apart (program.h).
#include <set>
#include <string>
#include <string_view>

namespace gpgpu {

/// Names declared by `uniform` declarations in `glsl` (comments skipped; `uniform T a, b[4] = ...;`
/// gives a and b; uniform blocks give nothing). Preprocessor conditionals are not evaluated, so a
/// name declared in any branch counts as declared.
[[nodiscard]] std::set<std::string> declared_uniforms(std::string_view glsl);

/// The declared name a uniform path refers to: "u_levels[3]" -> "u_levels", "u_light.pos" -> "u_light".
[[nodiscard]] std::string_view uniform_base_name(std::string_view path);

}  // namespace gpgpu
