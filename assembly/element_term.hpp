// The elements as a term of the equations of motion: each of the rank's elements' residual into its
// blocks' rows and its tangents, through the blocks' chain maps, into the Jacobian.
#pragma once

#include "assembly/dof_map.hpp"
#include "assembly/local_state.hpp"
#include "assembly/matrix_fill.hpp"

#include <mpi.h>
#include <petscmat.h>

#include <vector>

namespace latticedyn {

class ElementTerm {
 public:
  /// Plans the evaluation of the rank's elements: expensive ones on element_threads(comm)
  /// threads into buffers, cheap ones inline, runs of one type (Element::batch_size) together.
  ElementTerm(const Model& model, const DofMap& dofs, MPI_Comm comm);

  /// r += every element's residual (rotation rows through the slots' frame offsets). A failed
  /// evaluation writes NaN into its rows and is recorded in `errors`.
  void add_residual(const LocalState& s, const ElementContext& ctx, double* r, FirstError& errors);
  /// J += rows_I (cq K col_K_J + C col_C_J + M col_M_J) of every element (element_term.cpp); y
  /// takes its rotation rows (for the derivative of T^T). `direct`: fill_ready(J), the values go
  /// straight into J's arrays; otherwise through MatSetValues, and plan_fill(J) after assembly.
  PetscErrorCode add_jacobian(const LocalState& s, const ElementContext& ctx, double cq, double cv, double ca,
                              bool direct, Mat J, std::vector<Vec3>& y, FirstError& errors);
  /// Whether J's positions of the elements' blocks are known (every Jacobian after the first).
  bool fill_ready(Mat J) const { return fill_.ready_for(J); }
  /// Finds those positions in an assembled J.
  PetscErrorCode plan_fill(Mat J);

 private:
  PetscErrorCode add_element_jacobian(const LocalState& s, int local, const ElementEntry& entry,
                                      const ElementTangents& t, double cq, double cv, double ca, bool direct, Mat J,
                                      std::vector<Vec3>& y);

  const Model& model_;
  const DofMap& dofs_;
  // Expensive elements are evaluated on threads_ threads into buffers first (element_loop.hpp);
  // cheap ones inline, where a thread would cost more than it saves.
  int threads_ = 1;
  std::vector<int> threaded_;   // positions in local_elements() of the threaded elements
  std::vector<int> buffer_of_;  // per position in local_elements(): its buffer, or -1
  // Runs of consecutive elements of one type that evaluate together (Element::batch_size), never
  // mixing threaded and inline ones: per position, the first position of its run; at a run's
  // first position, its length.
  std::vector<int> run_first_, run_length_;
  std::vector<int> threaded_runs_;                 // first positions of the threaded runs
  std::vector<VecX> element_residuals_;            // per threaded element
  std::vector<ElementTangents> element_tangents_;  // per threaded element
  MatrixFill fill_;  // where the elements' blocks sit in the Jacobian, after its first assembly
};

}  // namespace latticedyn
