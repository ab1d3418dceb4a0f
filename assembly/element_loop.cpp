// Element kernels evaluated on several threads (OpenMP) within one MPI rank.
#include "assembly/element_loop.hpp"

#include <petscsys.h>

#include <omp.h>

#include <algorithm>
#include <mutex>

namespace latticedyn {

int element_threads(MPI_Comm comm) {
  PetscInt n = 0;
  PetscBool set = PETSC_FALSE;
  PetscOptionsGetInt(nullptr, nullptr, "-assembly_threads", &n, &set);
  int threads = 1;
  if (set) {
    threads = std::max<int>(1, static_cast<int>(n));
  } else {
    int size = 1;
    MPI_Comm_size(comm, &size);
    threads = size > 1 ? 1 : std::max(1, omp_get_max_threads());
  }
  // Elements that run parallel tasks inside (the super truss) take the same number.
  omp_set_num_threads(threads);
  return threads;
}

void parallel_for_each(int n, int threads, const std::function<void(int)>& body) {
  if (threads <= 1 || n <= 1) {
    for (int i = 0; i < n; ++i) body(i);
    return;
  }
  std::exception_ptr first;
  std::mutex guard;
  // Chunks of about 1/8 of a thread's share: few hand-outs for thousands of cheap elements,
  // single items for a handful of expensive ones.
  const int chunk = std::max(1, n / (8 * threads));
#pragma omp parallel for schedule(dynamic, chunk) num_threads(threads)
  for (int i = 0; i < n; ++i) {
    try {
      body(i);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(guard);
      if (!first) first = std::current_exception();
    }
  }
  if (first) std::rethrow_exception(first);
}

}  // namespace latticedyn
