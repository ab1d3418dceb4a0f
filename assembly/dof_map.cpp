// DoF numbering: block graph from elements and constraints, METIS k-way partition when running on
// several ranks, contiguous per-rank numbering, and nonzero counts for exact preallocation.
#include "assembly/dof_map.hpp"

#include <metis.h>

#include <algorithm>
#include <stdexcept>

namespace latticedyn {

namespace {
void add_unique(std::vector<int>& v, int x) {
  if (x >= 0 && std::find(v.begin(), v.end(), x) == v.end()) v.push_back(x);
}
}  // namespace

std::vector<int> element_blocks(const Model& model, int e) {
  std::vector<int> out;
  for (const auto& s : model.elements[e].slots)
    if (!model.blocks[s.block].fixed) add_unique(out, s.block);
  return out;
}

std::vector<int> joint_blocks(const Model& model, int j) {
  std::vector<int> out;
  const Joint& jt = model.joints[j];
  if (!model.blocks[jt.translation_block].fixed) add_unique(out, jt.translation_block);
  if (jt.rotation_block >= 0 && !model.blocks[jt.rotation_block].fixed) add_unique(out, jt.rotation_block);
  return out;
}

DofMap::DofMap(const Model& model, int rank, int size) : model_(model), rank_(rank), size_(size) {
  build_graph();
  partition();
  number();
}

void DofMap::build_graph() {
  const int nb = static_cast<int>(model_.blocks.size());
  // Every coupling appended, then sorted and made unique once per block: linear in the couplings
  // (a set per block cost an allocation per entry: 1.3 s for a million unknowns).
  graph_.assign(nb, {});
  for (int b = 0; b < nb; ++b)
    if (!model_.blocks[b].fixed) graph_[b].push_back(b);
  auto couple = [&](const std::vector<int>& blocks) {
    for (int a : blocks) graph_[a].insert(graph_[a].end(), blocks.begin(), blocks.end());
  };
  for (int e = 0; e < static_cast<int>(model_.elements.size()); ++e) couple(element_blocks(model_, e));
  const int nc = static_cast<int>(model_.constraints.size());
  constraint_blocks_.assign(nc, {});
  block_constraints_.assign(nb, {});
  for (int c = 0; c < nc; ++c) {
    std::vector<int> blocks = joint_blocks(model_, model_.constraints[c].joint1);
    for (int b : joint_blocks(model_, model_.constraints[c].joint2)) add_unique(blocks, b);
    if (blocks.empty()) throw ModelError("constraint '" + model_.constraints[c].name + "' acts on no free DoF");
    couple(blocks);  // d(G^T lambda)/dq couples all blocks of the constraint
    std::sort(blocks.begin(), blocks.end());
    for (int b : blocks) block_constraints_[b].push_back(c);
    constraint_blocks_[c] = std::move(blocks);
  }
  for (auto& row : graph_) {
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
  }
}

void DofMap::partition() {
  const int nb = static_cast<int>(model_.blocks.size());
  block_part_.assign(nb, 0);
  std::vector<int> free_blocks;
  for (int b = 0; b < nb; ++b)
    if (!model_.blocks[b].fixed) free_blocks.push_back(b);
  const int nv = static_cast<int>(free_blocks.size());
  if (size_ == 1 || nv == 0) return;

  // A node's translation block and the rotation block after it stay together (one vertex): cutting
  // between them saves nothing, and kept side by side they make the 6 x 6 blocks a block matrix
  // factors fastest (SystemAssembler::uniform_blocks).
  std::vector<int> first_of, second_of;  // per vertex its block, and the rotation paired with it or -1
  std::vector<idx_t> vertex(nb, -1);
  for (int i = 0; i < nv; ++i) {
    const int b = free_blocks[i];
    vertex[b] = static_cast<idx_t>(first_of.size());
    second_of.push_back(-1);
    if (i + 1 < nv && model_.blocks[b].kind == SlotKind::translation &&
        model_.blocks[free_blocks[i + 1]].kind == SlotKind::rotation &&
        std::binary_search(graph_[b].begin(), graph_[b].end(), free_blocks[i + 1])) {
      second_of.back() = free_blocks[++i];
      vertex[second_of.back()] = static_cast<idx_t>(first_of.size());
    }
    first_of.push_back(b);
  }
  const int nvertices = static_cast<int>(first_of.size());
  std::vector<idx_t> xadj(1, 0), adjncy, vwgt(nvertices, 0);
  for (int v = 0; v < nvertices; ++v) {
    const std::size_t start = adjncy.size();
    for (int b : {first_of[v], second_of[v]}) {
      if (b < 0) continue;
      vwgt[v] += model_.blocks[b].size();
      for (int c : graph_[b])
        if (vertex[c] != v) adjncy.push_back(vertex[c]);
    }
    std::sort(adjncy.begin() + static_cast<std::ptrdiff_t>(start), adjncy.end());
    adjncy.erase(std::unique(adjncy.begin() + static_cast<std::ptrdiff_t>(start), adjncy.end()), adjncy.end());
    xadj.push_back(static_cast<idx_t>(adjncy.size()));
  }
  std::vector<idx_t> part(nvertices, 0);
  idx_t nvtxs = nvertices, ncon = 1, nparts = size_, objval = 0;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED] = 1;  // every rank must compute the same partition
  // Parts within 0.1 % of each other instead of METIS's 3 %: the slowest rank sets every step's
  // pace (lattice-bays on 2 ranks: 1.029 of the mean before).
  options[METIS_OPTION_UFACTOR] = 1;
  int status = METIS_ERROR;
  if (nvertices >= 2 * size_ && !adjncy.empty())
    status = METIS_PartGraphKway(&nvtxs, &ncon, xadj.data(), adjncy.data(), vwgt.data(), nullptr, nullptr,
                                 &nparts, nullptr, nullptr, options, &objval, part.data());
  if (status != METIS_OK) {
    // Tiny or edgeless graphs: contiguous chunks are as good as any partition.
    for (int i = 0; i < nvertices; ++i) part[i] = static_cast<idx_t>((static_cast<long>(i) * size_) / nvertices);
  }
  for (int b : free_blocks) block_part_[b] = static_cast<int>(part[vertex[b]]);
}

void DofMap::number() {
  const int nb = static_cast<int>(model_.blocks.size());
  const int nc = static_cast<int>(model_.constraints.size());
  constraint_part_.assign(nc, 0);
  for (int c = 0; c < nc; ++c) constraint_part_[c] = block_part_[constraint_blocks_[c].front()];

  block_dof_.assign(nb, -1);
  multiplier_dof_.assign(nc, -1);
  range_.assign(size_ + 1, 0);
  int next = 0;
  num_multipliers_ = 0;
  for (int p = 0; p < size_; ++p) {
    range_[p] = next;
    for (int b = 0; b < nb; ++b)
      if (!model_.blocks[b].fixed && block_part_[b] == p) {
        block_dof_[b] = next;
        next += model_.blocks[b].size();
      }
    for (int c = 0; c < nc; ++c)
      if (constraint_part_[c] == p) {
        multiplier_dof_[c] = next;
        next += model_.constraints[c].rows();
        num_multipliers_ += model_.constraints[c].rows();
      }
  }
  range_[size_] = next;
  global_size_ = next;

  std::vector<char> needed(nb, 0);
  for (int b = 0; b < nb; ++b)
    if (!model_.blocks[b].fixed && block_part_[b] == rank_) needed[b] = 1;
  for (int e = 0; e < static_cast<int>(model_.elements.size()); ++e) {
    const auto blocks = element_blocks(model_, e);
    if (blocks.empty() || block_part_[blocks.front()] != rank_) continue;
    local_elements_.push_back(e);
    for (int b : blocks) needed[b] = 1;
  }
  for (int c = 0; c < nc; ++c) {
    if (constraint_part_[c] != rank_) continue;
    local_constraints_.push_back(c);
    for (int b : constraint_blocks_[c]) needed[b] = 1;
  }
  for (int l = 0; l < static_cast<int>(model_.loads.size()); ++l) {
    const auto blocks = joint_blocks(model_, model_.loads[l].joint);
    if (blocks.empty() || block_part_[blocks.front()] != rank_) continue;
    local_loads_.push_back(l);
    for (int b : blocks) needed[b] = 1;
  }
  for (int b = 0; b < nb; ++b)
    if (needed[b]) needed_blocks_.push_back(b);
}

void DofMap::count_nonzeros(std::vector<int>& diagonal, std::vector<int>& off_diagonal) const {
  const int lo = owned_begin(), hi = owned_end();
  diagonal.assign(hi - lo, 0);
  off_diagonal.assign(hi - lo, 0);
  auto add_columns = [&](int row, int first, int count) {
    for (int k = 0; k < count; ++k) {
      const int col = first + k;
      (col >= lo && col < hi ? diagonal : off_diagonal)[row - lo] += 1;
    }
  };
  const int nb = static_cast<int>(model_.blocks.size());
  for (int b = 0; b < nb; ++b) {
    if (model_.blocks[b].fixed || block_part_[b] != rank_) continue;
    for (int i = 0; i < model_.blocks[b].size(); ++i) {
      const int row = block_dof_[b] + i;
      for (int c : graph_[b]) add_columns(row, block_dof_[c], model_.blocks[c].size());
      for (int c : block_constraints_[b]) add_columns(row, multiplier_dof_[c], model_.constraints[c].rows());
    }
  }
  for (int c : local_constraints_) {
    for (int i = 0; i < model_.constraints[c].rows(); ++i) {
      const int row = multiplier_dof_[c] + i;
      for (int b : constraint_blocks_[c]) add_columns(row, block_dof_[b], model_.blocks[b].size());
      add_columns(row, row, 1);  // explicit zero diagonal: keeps every row's diagonal in the pattern
    }
  }
}

namespace {

// Calls f(global index, model-order index, count) for every free block and constraint.
template <class F>
void for_each_range(const Model& model, const std::vector<int>& block_dof, const std::vector<int>& multiplier_dof, F f) {
  int next = 0;
  for (std::size_t b = 0; b < model.blocks.size(); ++b)
    if (!model.blocks[b].fixed) {
      f(block_dof[b], next, model.blocks[b].size());
      next += model.blocks[b].size();
    }
  for (std::size_t c = 0; c < model.constraints.size(); ++c) {
    f(multiplier_dof[c], next, model.constraints[c].rows());
    next += model.constraints[c].rows();
  }
}

}  // namespace

std::vector<double> DofMap::to_model_order(std::span<const double> global) const {
  if (static_cast<int>(global.size()) != global_size_) throw std::invalid_argument("to_model_order: wrong vector size");
  std::vector<double> out(global.size());
  for_each_range(model_, block_dof_, multiplier_dof_, [&](int g, int m, int n) {
    std::copy(global.begin() + g, global.begin() + g + n, out.begin() + m);
  });
  return out;
}

std::vector<double> DofMap::from_model_order(std::span<const double> ordered) const {
  if (static_cast<int>(ordered.size()) != global_size_) throw std::invalid_argument("from_model_order: wrong vector size");
  std::vector<double> out(ordered.size());
  for_each_range(model_, block_dof_, multiplier_dof_, [&](int g, int m, int n) {
    std::copy(ordered.begin() + m, ordered.begin() + m + n, out.begin() + g);
  });
  return out;
}

}  // namespace latticedyn
