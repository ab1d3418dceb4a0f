// Element kernels evaluated on several threads (OpenMP) within one MPI rank: the kernels are
// independent and const, only their insertion into PETSc objects has to stay serial.
#pragma once

#include <mpi.h>

#include <exception>
#include <functional>

namespace latticedyn {

/// Threads for element evaluation: the PETSc option -assembly_threads N if given, else all the
/// cores OpenMP sees (OMP_NUM_THREADS) when the run has one rank, and 1 under several ranks
/// (each rank already has a core). Always at least 1. Sets OpenMP's thread count to it, for the
/// elements that run parallel tasks themselves.
int element_threads(MPI_Comm comm);

/// Calls body(i) for i = 0..n-1 on `threads` threads, the items handed out in small chunks
/// (element costs differ by orders of magnitude: a super truss against a strut tie). The first exception
/// thrown by a call is rethrown here after all threads have stopped.
void parallel_for_each(int n, int threads, const std::function<void(int)>& body);

}  // namespace latticedyn
