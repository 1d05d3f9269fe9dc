// libFuzzer target: STEP text through the reader, then the whole-model checks every command runs
// first (model size and its validation, the faces in world coordinates). ReadError is the expected
// answer to bad input; anything else (another exception, a crash, a sanitizer report) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/model_checks.h"
#include "nurbs/io/step_reader.h"
#include "nurbs/io/read_error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    fuzz::whole_model_checks(nurbs::io::read_step_text(std::string(reinterpret_cast<const char*>(data), size), "fuzz.stp"));
  } catch (const nurbs::io::ReadError&) {
  }
  return 0;
}
