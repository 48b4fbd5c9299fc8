// libFuzzer target of the OBJ reader (read_and_check.hpp).
#include "read_and_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  isoquad::fuzz::read_and_check(data, size, isoquad::MeshFormat::obj);
  return 0;
}
