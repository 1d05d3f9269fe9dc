// libFuzzer target: .bpt text (the Bezier patch format) through its reader, then the whole-model
// checks every command runs first. ReadError is the expected answer to bad input.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/model_checks.h"
#include "nurbs/io/bpt_reader.h"
#include "nurbs/io/read_error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    fuzz::whole_model_checks(nurbs::io::read_bpt_text(std::string(reinterpret_cast<const char*>(data), size), "fuzz.bpt"));
  } catch (const nurbs::io::ReadError&) {
  }
  return 0;
}
