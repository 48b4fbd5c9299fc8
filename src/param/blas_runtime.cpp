#include "param/blas_runtime.hpp"

#include <dlfcn.h>

namespace isoquad {

namespace {

struct BlasRuntime {
  std::mutex mutex;
  bool serialize = false;

  // Looked up at run time, so that isoquad links against the generic libblas.so.3 and runs on
  // any BLAS; these two symbols exist only in OpenBLAS.
  BlasRuntime() {
    using SetThreads = void (*)(int);
    using GetParallel = int (*)();
    if (void* set = dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))
      reinterpret_cast<SetThreads>(set)(1);
    if (void* get = dlsym(RTLD_DEFAULT, "openblas_get_parallel"))
      serialize = reinterpret_cast<GetParallel>(get)() == 0;  // 0: the sequential build
  }
};

}  // namespace

std::unique_lock<std::mutex> blas_section() {
  static BlasRuntime runtime;
  return runtime.serialize ? std::unique_lock<std::mutex>(runtime.mutex)
                           : std::unique_lock<std::mutex>();
}

}  // namespace isoquad
