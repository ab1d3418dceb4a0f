// PETSc's own LU on saddle-point matrices: a fill-reducing permutation with the rows that lack a
// pivot of their own moved behind rows that give them one, and the fallback to UMFPACK.
#include "timestepping/native_lu.hpp"

#include "timestepping/elimination_fill.hpp"

#include <algorithm>
#include <functional>
#include <numeric>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace latticedyn {

namespace {

// Rows named by an IS composed on A under `name` (flags[i] = 1), if there is one.
PetscErrorCode mark_named_rows(Mat A, const char* name, std::vector<char>& flags, PetscBool* found) {
  PetscObject named = nullptr;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectQuery((PetscObject)A, name, &named));
  *found = named ? PETSC_TRUE : PETSC_FALSE;
  if (!named) PetscFunctionReturn(0);
  const PetscInt* rows;
  PetscInt m;
  PetscCall(ISGetLocalSize((IS)named, &m));
  PetscCall(ISGetIndices((IS)named, &rows));
  for (PetscInt k = 0; k < m; ++k) flags[rows[k]] = 1;
  PetscCall(ISRestoreIndices((IS)named, &rows));
  PetscFunctionReturn(0);
}

// A delayed row is placed just after the last placed row it couples to, once it can have a
// pivot there. The factorisation gives a multiplier a nonzero pivot when an unknown it couples to
// has been eliminated that no earlier multiplier relies on (a body of six coordinates carries six
// multipliers, not more), and a frame held only by constraints a pivot for each of its rows when as
// many multipliers coupled to it have been eliminated. So, pass by pass, the rows that can be
// placed are matched (Kuhn's augmenting paths) to partners of that kind not yet taken: placed
// unknowns (stiff or frame) for multipliers, placed multipliers for frame rows. Offsets of 1/2,
// 1/4, ... keep every pass between the same two ordinary rows. Rows that never find a partner
// (dependent constraints) keep their first place; the factorisation then reports a zero pivot.
PetscErrorCode place_delayed_rows(const std::vector<char>& multiplier, const std::vector<char>& frame,
                                  const std::vector<std::vector<PetscInt>>& coupled, std::vector<double>& key) {
  PetscFunctionBeginUser;
  const auto n = static_cast<PetscInt>(key.size());
  std::vector<char> placed(n);
  for (PetscInt i = 0; i < n; ++i) placed[i] = !multiplier[i] && !frame[i];
  std::vector<PetscInt> taken_by(n, -1);  // partner -> the delayed row it gives its pivot to
  std::vector<long> visited(n, -1);       // the search that last visited a partner (no clearing)
  long search = 0;
  // Does row i find a partner, possibly taking one from another row of this pass (which must then
  // find another)? Partners taken in earlier passes stay.
  std::vector<char> in_pass(n, 0);
  auto eligible = [&](PetscInt i, PetscInt j) {
    return placed[j] && (multiplier[i] ? !multiplier[j] : multiplier[j] != 0);
  };
  std::function<bool(PetscInt)> augment = [&](PetscInt i) {
    for (PetscInt j : coupled[i]) {
      if (!eligible(i, j) || visited[j] == search) continue;
      visited[j] = search;
      if (taken_by[j] < 0 || (in_pass[taken_by[j]] && augment(taken_by[j]))) {
        taken_by[j] = i;
        return true;
      }
    }
    return false;
  };
  double offset = 0.5;
  for (bool progress = true; progress && offset > 1e-12; offset *= 0.5) {
    progress = false;
    std::vector<PetscInt> candidates;
    for (PetscInt i = 0; i < n; ++i)
      if (!placed[i]) {
        bool reachable = false;
        for (PetscInt j : coupled[i]) reachable = reachable || eligible(i, j);
        if (reachable) candidates.push_back(i), in_pass[i] = 1;
      }
    std::vector<PetscInt> matched;
    for (PetscInt i : candidates) {
      ++search;
      if (augment(i)) matched.push_back(i);
    }
    // A row that lost its partner to a later one of the pass was re-matched by the augmenting path,
    // so every row in `matched` holds a partner now.
    for (PetscInt i : candidates) in_pass[i] = 0;
    for (PetscInt i : matched) {
      double last = -1.0;
      for (PetscInt j : coupled[i])
        if (placed[j]) last = std::max(last, key[j]);
      key[i] = last + offset;
    }
    for (PetscInt i : matched) placed[i] = 1, progress = true;
  }
  PetscFunctionReturn(0);
}

// Does the block matrix's own order factor with no more work than `permuted` (block rows), give or
// take 5 %? Counted on the block graph (elimination_cost), not by factoring.
PetscErrorCode natural_order_suffices(Mat A, IS permuted, PetscBool* natural) {
  PetscFunctionBeginUser;
  *natural = PETSC_FALSE;
  PetscInt blocks;
  const PetscInt *ia, *ja;
  PetscBool done;
  PetscCall(MatGetRowIJ(A, 0, PETSC_TRUE, PETSC_TRUE, &blocks, &ia, &ja, &done));
  if (!done) PetscFunctionReturn(0);
  PetscInt m;
  PetscCall(ISGetLocalSize(permuted, &m));
  if (m == blocks) {
    std::vector<PetscInt> own(blocks);
    std::iota(own.begin(), own.end(), PetscInt{0});
    const PetscInt* perm;
    PetscCall(ISGetIndices(permuted, &perm));
    const std::span<const PetscInt> start(ia, blocks + 1), columns(ja, ia[blocks]);
    EliminationCost as_is, reordered;
    try {  // nothing may unwind through PETSc; a count that cannot be made keeps minimum degree
      as_is = elimination_cost(start, columns, own);
      reordered = elimination_cost(start, columns, std::span<const PetscInt>(perm, blocks));
      *natural = as_is.work <= 1.05 * reordered.work ? PETSC_TRUE : PETSC_FALSE;
    } catch (const std::exception&) {
      *natural = PETSC_FALSE;
    }
    PetscCall(ISRestoreIndices(permuted, &perm));
    PetscCall(PetscInfo(A, "block order: own %g, minimum degree %g (work of L, blocks): %s\n", as_is.work,
                        reordered.work, *natural ? "own order" : "minimum degree"));
  }
  PetscCall(MatRestoreRowIJ(A, 0, PETSC_TRUE, PETSC_TRUE, &blocks, &ia, &ja, &done));
  PetscFunctionReturn(0);
}

PetscErrorCode saddle_point_ordering(Mat A, MatOrderingType, IS* row, IS* col) {
  PetscFunctionBeginUser;
  PetscInt n;
  PetscCall(MatGetSize(A, &n, nullptr));
  // Approximate minimum degree (SuiteSparse's, through PETSc) where PETSc has it: on the full
  // crane its factors take half the flops of reverse Cuthill-McKee's, on lattices the same.
  PetscErrorCode (*amd)(Mat, MatOrderingType, IS*, IS*) = nullptr;
  // (MatGetOrdering, which calls this function, has filled MatOrderingList.)
  PetscCall(PetscFunctionListFind(MatOrderingList, MATORDERINGAMD, &amd));
  IS base_row, base_col;
  PetscCall(MatGetOrdering(A, amd ? MATORDERINGAMD : MATORDERINGRCM, &base_row, &base_col));
  PetscInt bs;
  PetscCall(MatGetBlockSize(A, &bs));
  PetscBool baij;
  PetscCall(PetscObjectTypeCompare((PetscObject)A, MATSEQBAIJ, &baij));
  if (baij && bs > 1) {
    // A block matrix (SystemAssembler::create_matrix with uniform blocks) has no rows without a
    // pivot; its orderings permute blocks.
    PetscBool natural;
    PetscCall(natural_order_suffices(A, base_row, &natural));
    if (!natural) {
      *row = base_row;
      *col = base_col;
      PetscFunctionReturn(0);
    }
    // PETSc then factors and solves with its natural-ordering kernels, without the permutation's
    // indirection: on lattice-bays, whose model order is a chain along the lattice, the same flops
    // as block AMD in 10 % less time (docs/performance.md).
    PetscInt blocks;
    PetscCall(ISGetLocalSize(base_row, &blocks));
    PetscCall(ISDestroy(&base_row));
    PetscCall(ISDestroy(&base_col));
    PetscCall(ISCreateStride(PETSC_COMM_SELF, blocks, 0, 1, row));
    PetscCall(ISCreateStride(PETSC_COMM_SELF, blocks, 0, 1, col));
    PetscCall(ISSetPermutation(*row));
    PetscCall(ISSetPermutation(*col));
    PetscFunctionReturn(0);
  }
  const PetscInt* perm;
  PetscCall(ISGetIndices(base_row, &perm));
  std::vector<double> key(n);
  for (PetscInt k = 0; k < n; ++k) key[perm[k]] = static_cast<double>(k);
  PetscCall(ISRestoreIndices(base_row, &perm));
  PetscCall(ISDestroy(&base_row));
  PetscCall(ISDestroy(&base_col));
  const std::vector<double> position = key;

  // Rows without a pivot of their own: multipliers, and frames only constraints hold. Without the
  // assembler's lists, the rows with a zero diagonal count as multipliers.
  std::vector<char> multiplier(n, 0), frame(n, 0);
  PetscBool named;
  PetscCall(mark_named_rows(A, kMultiplierRows, multiplier, &named));
  PetscCall(mark_named_rows(A, kUnstiffenedRows, frame, &named));
  if (!named) {
    for (PetscInt i = 0; i < n; ++i) {
      PetscInt nz;
      const PetscInt* cols;
      const PetscScalar* vals;
      PetscCall(MatGetRow(A, i, &nz, &cols, &vals));
      multiplier[i] = 1;
      for (PetscInt k = 0; k < nz; ++k)
        if (cols[k] == i && vals[k] != 0.0) multiplier[i] = 0;
      PetscCall(MatRestoreRow(A, i, &nz, &cols, &vals));
    }
  }

  // The delayed rows' couplings (the pattern of their rows), read once.
  std::vector<std::vector<PetscInt>> coupled(n);
  for (PetscInt i = 0; i < n; ++i) {
    if (!multiplier[i] && !frame[i]) continue;
    PetscInt nz;
    const PetscInt* cols;
    PetscCall(MatGetRow(A, i, &nz, &cols, nullptr));
    for (PetscInt k = 0; k < nz; ++k)
      if (cols[k] != i) coupled[i].push_back(cols[k]);
    PetscCall(MatRestoreRow(A, i, &nz, &cols, nullptr));
  }
  PetscCall(place_delayed_rows(multiplier, frame, coupled, key));
  std::vector<PetscInt> order(n);
  std::iota(order.begin(), order.end(), PetscInt{0});
  std::stable_sort(order.begin(), order.end(), [&](PetscInt a, PetscInt b) {
    return key[a] < key[b] || (key[a] == key[b] && position[a] < position[b]);
  });
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, n, order.data(), PETSC_COPY_VALUES, row));
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, n, order.data(), PETSC_COPY_VALUES, col));
  PetscCall(ISSetPermutation(*row));
  PetscCall(ISSetPermutation(*col));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode register_saddle_point_ordering() {
  static bool registered = false;
  PetscFunctionBeginUser;
  if (registered) PetscFunctionReturn(0);
  PetscCall(MatOrderingRegister(kSaddlePointOrdering, saddle_point_ordering));
  registered = true;
  PetscFunctionReturn(0);
}

PetscErrorCode use_native_lu(KSP ksp) {
  PC pc;
  PetscFunctionBeginUser;
  PetscCall(register_saddle_point_ordering());
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCLU));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERPETSC));
  PetscCall(PCFactorSetMatOrderingType(pc, kSaddlePointOrdering));
  PetscFunctionReturn(0);
}

PetscErrorCode recover_from_failed_factorisation(KSP ksp, PetscBool* reset) {
  PC pc;
  PCFailedReason reason;
  PetscBool lu;
  MatSolverType type = nullptr;
  PetscFunctionBeginUser;
  *reset = PETSC_FALSE;
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCGetFailedReason(pc, &reason));
  if (reason == PC_NOERROR) PetscFunctionReturn(0);
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCLU, &lu));
  if (!lu) PetscFunctionReturn(0);
  PetscCall(PCFactorGetMatSolverType(pc, &type));
  const bool native = type && std::string_view(type) == MATSOLVERPETSC;
  const std::string package = type ? type : "";  // PCReset frees the string type points to
  PetscCall(PetscInfo(pc, "the factorisation by %s failed (%s): %s\n", package.c_str(), PCFailedReasons[reason],
                      native ? "UMFPACK, which pivots, from here on" : "set up anew"));
  if (package == MATSOLVERMUMPS && reason == PC_FACTOR_OUTMEMORY) {
    // Delayed pivots outgrew MUMPS's working space: twice as much for the next factorisation.
    PetscInt relax = 100;
    PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-mat_mumps_icntl_14", &relax, nullptr));
    const std::string doubled = std::to_string(2 * std::max<PetscInt>(relax, 50));
    PetscCall(PetscOptionsSetValue(nullptr, "-mat_mumps_icntl_14", doubled.c_str()));
  }
  // PCReset drops the operators too: keep them and hand them back.
  Mat A, P;
  PetscCall(KSPGetOperators(ksp, &A, &P));
  PetscCall(PetscObjectReference((PetscObject)A));
  PetscCall(PetscObjectReference((PetscObject)P));
  PetscCall(PCReset(pc));
  PetscCall(PCSetType(pc, PCLU));
  if (native) {
    PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERUMFPACK));
    PetscCall(PCFactorSetMatOrderingType(pc, MATORDERINGEXTERNAL));
  } else {
    PetscCall(PCFactorSetMatSolverType(pc, package.c_str()));
  }
  PetscCall(KSPSetOperators(ksp, A, P));
  PetscCall(MatDestroy(&A));
  PetscCall(MatDestroy(&P));
  *reset = PETSC_TRUE;
  PetscFunctionReturn(0);
}

}  // namespace latticedyn
