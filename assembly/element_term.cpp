// The rank's elements into its residual rows and Jacobian blocks: expensive elements evaluated on
// threads into buffers first, the rest inline; runs of one type as one batch; insertion serial.
#include "assembly/element_term.hpp"

#include "assembly/element_loop.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <typeinfo>

namespace latticedyn {

ElementTerm::ElementTerm(const Model& model, const DofMap& dofs, MPI_Comm comm) : model_(model), dofs_(dofs) {
  threads_ = element_threads(comm);
  const std::vector<int>& elements = dofs_.local_elements();
  buffer_of_.assign(elements.size(), -1);
  for (std::size_t i = 0; i < elements.size(); ++i)
    if (threads_ > 1 && model_.elements[elements[i]].element->expensive()) {
      buffer_of_[i] = static_cast<int>(threaded_.size());
      threaded_.push_back(static_cast<int>(i));
    }
  if (threaded_.size() < 2) {  // nothing to share out
    threaded_.clear();
    buffer_of_.assign(elements.size(), -1);
  }
  element_residuals_.resize(threaded_.size());
  element_tangents_.resize(threaded_.size());
  run_first_.assign(elements.size(), -1);
  run_length_.assign(elements.size(), 0);
  for (std::size_t i = 0; i < elements.size();) {
    const Element& e = *model_.elements[elements[i]].element;
    const std::size_t width = static_cast<std::size_t>(std::clamp(e.batch_size(), 1, kMaxElementBatch));
    // A run is elements of one type (one batched kernel) that are all threaded or all not.
    auto joins_run = [&](std::size_t k) {
      const Element& other = *model_.elements[elements[k]].element;
      return typeid(other) == typeid(e) && (buffer_of_[k] < 0) == (buffer_of_[i] < 0);
    };
    std::size_t n = 1;
    while (n < width && i + n < elements.size() && joins_run(i + n)) ++n;
    for (std::size_t k = 0; k < n; ++k) run_first_[i + k] = static_cast<int>(i);
    run_length_[i] = static_cast<int>(n);
    if (buffer_of_[i] >= 0) threaded_runs_.push_back(static_cast<int>(i));  // buffers i..i+n-1 are consecutive
    i += n;
  }
}

void ElementTerm::add_residual(const LocalState& s, const ElementContext& ctx, double* r, FirstError& errors) {
  const std::vector<int>& elements = dofs_.local_elements();
  auto evaluate = [&](int first, VecX* out) {
    const ElementRun run = gather_run(model_, elements, first, run_length_[first], s.state);
    try {
      if (run.count == 1) {
        out[0].resize(run.elements[0]->num_dofs());
        run.elements[0]->residual(run.states[0], ctx, out[0]);
      } else {
        run.elements[0]->residual_batch(run.element_span(), run.state_span(), ctx, {out, run.size()});
      }
    } catch (...) {
      // Outside an element's domain (a rope's rest length through zero), or any other failure of
      // its evaluation: NaN marks the residual not finite, so the integrator cuts the step (a
      // domain error) instead of an exception unwinding through PETSc.
      errors.record_current_exception("a " + std::string(run.elements[0]->type_name()) + " element");
      for (int k = 0; k < run.count; ++k) out[k].setConstant(run.elements[k]->num_dofs(), std::nan(""));
    }
  };
  parallel_for_each(static_cast<int>(threaded_runs_.size()), threads_, [&](int k) {
    evaluate(threaded_runs_[k], &element_residuals_[buffer_of_[threaded_runs_[k]]]);
  });
  thread_local std::array<VecX, kMaxElementBatch> inline_re;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const ElementEntry& entry = model_.elements[elements[i]];
    const auto kinds = entry.element->slots();
    if (buffer_of_[i] < 0 && run_first_[i] == static_cast<int>(i)) evaluate(static_cast<int>(i), inline_re.data());
    const VecX& re = buffer_of_[i] < 0 ? inline_re[i - run_first_[i]] : element_residuals_[buffer_of_[i]];
    int o = 0;
    for (std::size_t k = 0; k < kinds.size(); ++k) {
      const int n = slot_size(kinds[k]);
      const int lo = s.offset(entry.slots[k].block);
      if (lo >= 0) {
        if (kinds[k] == SlotKind::rotation) {
          const Vec3 rb = entry.slots[k].offset * re.segment<3>(o);
          for (int i = 0; i < 3; ++i) r[lo + i] += rb(i);
        } else {
          for (int i = 0; i < n; ++i) r[lo + i] += re(o + i);
        }
      }
      o += n;
    }
  }
}

PetscErrorCode ElementTerm::add_jacobian(const LocalState& s, const ElementContext& ctx, double cq, double cv, double ca,
                                         bool direct, Mat J, std::vector<Vec3>& y, FirstError& errors) {
  PetscFunctionBeginUser;
  const std::vector<int>& elements = dofs_.local_elements();
  auto evaluate = [&](int first, ElementTangents* out) {
    const ElementRun run = gather_run(model_, elements, first, run_length_[first], s.state);
    try {
      if (run.count == 1)
        run.elements[0]->tangents(run.states[0], ctx, out[0]);
      else
        run.elements[0]->tangents_batch(run.element_span(), run.state_span(), ctx, {out, run.size()});
    } catch (...) {
      errors.record_current_exception("a " + std::string(run.elements[0]->type_name()) + " element");
      for (int k = 0; k < run.count; ++k) {
        out[k].resize(run.elements[k]->num_dofs());
        for (auto* m : {&out[k].K, &out[k].C, &out[k].M}) m->setConstant(std::nan(""));
        out[k].residual.setConstant(std::nan(""));
      }
    }
  };
  parallel_for_each(static_cast<int>(threaded_runs_.size()), threads_, [&](int k) {
    evaluate(threaded_runs_[k], &element_tangents_[buffer_of_[threaded_runs_[k]]]);
  });
  if (direct) PetscCall(fill_.begin(J));
  thread_local std::array<ElementTangents, kMaxElementBatch> inline_t;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const ElementEntry& entry = model_.elements[elements[i]];
    if (buffer_of_[i] < 0 && run_first_[i] == static_cast<int>(i)) evaluate(static_cast<int>(i), inline_t.data());
    const ElementTangents& t = buffer_of_[i] < 0 ? inline_t[i - run_first_[i]] : element_tangents_[buffer_of_[i]];
    PetscCall(add_element_jacobian(s, static_cast<int>(i), entry, t, cq, cv, ca, direct, J, y));
  }
  if (direct) PetscCall(fill_.end(J));
  PetscFunctionReturn(0);
}

// One element's tangents (K, C, M in its slots' frames) as J blocks rows_I (cq K col_K_J + C col_C_J
// + M col_M_J) of the blocks' chain maps, the slots' frame offsets O folded into them (a rotation
// slot sees R O: rows O, columns O^T), in fixed 3 x 3 sizes; a block of a translation, vector or
// scalar slot has the plain chain (I, I, cv I, ca I).
PetscErrorCode ElementTerm::add_element_jacobian(const LocalState& s, int local, const ElementEntry& entry,
                                                 const ElementTangents& t, double cq, double cv, double ca, bool direct,
                                                 Mat J, std::vector<Vec3>& y) {
  struct SlotMap {
    int block, n, offset;
    bool free, plain;
    Mat3 rows, colK, colC, colM;
  };
  PetscFunctionBeginUser;
  const auto kinds = entry.element->slots();
  const int ns = static_cast<int>(kinds.size());
  std::array<SlotMap, 8> maps;
  if (ns > static_cast<int>(maps.size())) throw std::logic_error("add_element_jacobian: more than 8 slots");
  int o = 0;
  for (int k = 0; k < ns; ++k) {
    SlotMap& m = maps[k];
    m.block = entry.slots[k].block;
    m.n = slot_size(kinds[k]);
    m.offset = o;
    m.free = !model_.blocks[m.block].fixed;
    m.plain = kinds[k] != SlotKind::rotation;
    if (!m.plain) {
      const BlockChain& c = s.chain[m.block];
      const Mat3& O = entry.slots[k].offset;
      m.rows = c.rows * O;
      m.colK = O.transpose() * c.col_K;
      m.colC = O.transpose() * c.col_C;
      m.colM = O.transpose() * c.col_M;
      y[m.block] += O * t.residual.segment<3>(o);
    }
    o += m.n;
  }
  const int n = o;
  // The element's block of J: columns through the column blocks' chain maps, then rows through
  // the row blocks'. Fixed 12 x 12 for the elements of two frames (beams, super trusses), else a
  // fixed maximum size: no heap traffic either way.
  using Local = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor, 36, 36>;
  if (n > 36) throw std::logic_error("add_element_jacobian: more than 36 DoFs");
  auto combine = [&](auto& out, const auto& K, const auto& C, const auto& M) {
    for (int kj = 0; kj < ns; ++kj) {
      const SlotMap& mj = maps[kj];
      if (!mj.free) continue;
      const int oj = mj.offset;
      if (mj.plain) {
        out.middleCols(oj, mj.n) = cq * K.middleCols(oj, mj.n);
        if (cv != 0.0) out.middleCols(oj, mj.n) += cv * C.middleCols(oj, mj.n);
        if (ca != 0.0) out.middleCols(oj, mj.n) += ca * M.middleCols(oj, mj.n);
      } else {
        const Mat3 colK = cq * mj.colK;
        out.template middleCols<3>(oj).noalias() = K.template middleCols<3>(oj).lazyProduct(colK);
        out.template middleCols<3>(oj).noalias() += C.template middleCols<3>(oj).lazyProduct(mj.colC);
        out.template middleCols<3>(oj).noalias() += M.template middleCols<3>(oj).lazyProduct(mj.colM);
      }
    }
    for (int ki = 0; ki < ns; ++ki) {
      const SlotMap& mi = maps[ki];
      if (!mi.free || mi.plain) continue;
      const Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 36> rowsi = out.middleRows(mi.offset, 3);
      out.middleRows(mi.offset, 3).noalias() = mi.rows.lazyProduct(rowsi);
    }
  };
  // Into the matrix: through MatSetValues, or straight into its value arrays at the planned
  // positions (the plan lists, row by row of each free slot i, one position per slot j; -1: fixed
  // column or a row of another rank).
  auto insert = [&](const auto& A) -> PetscErrorCode {
    PetscFunctionBeginUser;
    if (!direct) {
      thread_local std::vector<PetscInt> idx;
      idx.assign(n, -1);
      for (int k = 0; k < ns; ++k)
        if (maps[k].free)
          for (int i = 0; i < maps[k].n; ++i) idx[maps[k].offset + i] = dofs_.block_dof(maps[k].block) + i;
      // Fixed rows and columns go in as -1 indices, which MatSetValues skips.
      PetscCall(MatSetValues(J, n, idx.data(), n, idx.data(), A.data(), ADD_VALUES));  // A row-major here
      PetscFunctionReturn(0);
    }
    const PetscInt* plan = fill_.element_offsets(local);
    const PetscInt stride = fill_.column_stride();
    if (stride == 3 || stride == 6) {
      // BAIJ's blocks are column-major: a slot's 3 x 3 block starts at its first row's position,
      // its columns `stride` apart (a whole 3 x 3 block, or a quarter of a node's 6 x 6 one).
      // Every slot has three DoFs (uniform_blocks); rows of another rank go through MatSetValues.
      for (int ki = 0; ki < ns; ++ki) {
        const SlotMap& mi = maps[ki];
        if (!mi.free) continue;
        const PetscInt* row0 = plan;
        plan += 3 * ns;
        for (int kj = 0; kj < ns; ++kj) {
          const SlotMap& mj = maps[kj];
          if (!mj.free) continue;
          if (row0[kj] >= 0) {
            double* at = fill_.values(row0[kj]);
            if (stride == 3)
              Eigen::Map<Mat3>(at) += A.template block<3, 3>(mi.offset, mj.offset);
            else
              Eigen::Map<Mat3, 0, Eigen::OuterStride<6>>(at) += A.template block<3, 3>(mi.offset, mj.offset);
          } else {
            const PetscInt ri = dofs_.block_dof(mi.block), cj = dofs_.block_dof(mj.block);
            const PetscInt rows[3] = {ri, ri + 1, ri + 2}, cols[3] = {cj, cj + 1, cj + 2};
            const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> block = A.template block<3, 3>(mi.offset, mj.offset);
            PetscCall(MatSetValues(J, 3, rows, 3, cols, block.data(), ADD_VALUES));
          }
        }
      }
      PetscFunctionReturn(0);
    }
    for (int ki = 0; ki < ns; ++ki) {
      const SlotMap& mi = maps[ki];
      if (!mi.free) continue;
      for (int r = 0; r < mi.n; ++r, plan += ns) {
        const int ar = mi.offset + r;
        for (int kj = 0; kj < ns; ++kj) {
          const SlotMap& mj = maps[kj];
          if (!mj.free) continue;
          const PetscInt at = plan[kj];
          if (at >= 0) {
            double* v = fill_.values(at);
            for (int c = 0; c < mj.n; ++c) v[c * stride] += A(ar, mj.offset + c);
          } else {
            const PetscInt row = dofs_.block_dof(mi.block) + r, col = dofs_.block_dof(mj.block);
            const PetscInt cols[3] = {col, col + 1, col + 2};
            double vals[3];
            for (int c = 0; c < mj.n; ++c) vals[c] = A(ar, mj.offset + c);
            PetscCall(MatSetValues(J, 1, &row, mj.n, cols, vals, ADD_VALUES));
          }
        }
      }
    }
    PetscFunctionReturn(0);
  };
  if (n == 12 && ns == 4) {
    using Map12 = Eigen::Map<const Mat12>;
    Mat12 A12;  // column-major: the column maps write whole columns
    combine(A12, Map12(t.K.data()), Map12(t.C.data()), Map12(t.M.data()));
    if (direct) {
      PetscCall(insert(A12));
    } else {
      const Eigen::Matrix<double, 12, 12, Eigen::RowMajor> rows = A12;  // MatSetValues reads rows
      PetscCall(insert(rows));
    }
  } else {
    thread_local Local A;
    A.resize(n, n);
    combine(A, t.K, t.C, t.M);
    PetscCall(insert(A));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode ElementTerm::plan_fill(Mat J) {
  PetscFunctionBeginUser;
  PetscCall(fill_.open(J));
  const std::vector<int>& elements = dofs_.local_elements();
  try {
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const ElementEntry& entry = model_.elements[elements[i]];
    const auto kinds = entry.element->slots();
    fill_.start_element();
    for (std::size_t ki = 0; ki < kinds.size(); ++ki) {
      const int bi = entry.slots[ki].block;
      if (model_.blocks[bi].fixed) continue;
      for (int r = 0; r < slot_size(kinds[ki]); ++r)
        for (std::size_t kj = 0; kj < kinds.size(); ++kj) {
          const int bj = entry.slots[kj].block;
          fill_.add_position(dofs_.block_dof(bi) + r, model_.blocks[bj].fixed ? -1 : dofs_.block_dof(bj));
        }
    }
  }
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_PLIB, "%s", e.what());  // no exception crosses into PETSc
  }
  PetscCall(fill_.close());
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
