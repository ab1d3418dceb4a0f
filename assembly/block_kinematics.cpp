// Block kinematics and chain maps for both parametrisations of the rates.
#include "assembly/block_kinematics.hpp"

#include "core/rotation.hpp"

#include <stdexcept>

namespace latticedyn {

void block_kinematics(const DofBlock& block, const double* u, const double* v, const double* a,
                      Parametrization param, BlockState& s, BlockChain* chain, double cq, double cv,
                      double ca) {
  const int n = block.size();
  auto vec = [&](const double* p) {
    Vec3 x = Vec3::Zero();
    if (p)
      for (int i = 0; i < n; ++i) x(i) = p[i];
    return x;
  };
  if (chain) {
    chain->rows.setIdentity();
    chain->col_K.setIdentity();
    chain->col_C = cv * Mat3::Identity();
    chain->col_M = ca * Mat3::Identity();
  }
  if (block.fixed || !u) {
    s.pos = block.position0;
    s.rot = block.orientation0;
    if (block.held) s.vel = block.velocity0;
    else s.vel.setZero();
    s.acc.setZero();
    return;
  }
  switch (block.kind) {
    case SlotKind::translation:
    case SlotKind::vector:
    case SlotKind::scalar:
      s.pos = vec(u);
      s.vel = vec(v);
      s.acc = vec(a);
      return;
    case SlotKind::rotation:
      break;
  }
  const Vec3 phi = vec(u);
  if (param == Parametrization::velocity_variables) {
    s.rot = block.orientation0 * rotation_matrix(phi);
    s.vel = vec(v);
    s.acc = vec(a);
    if (chain) chain->col_K = tangent_operator(phi);
    return;
  }
  const RotationChain rc = rotation_chain(block.orientation0, phi, vec(v), vec(a), chain != nullptr);
  s.rot = rc.R;
  s.vel = rc.omega;
  s.acc = rc.omega_dot;
  if (chain) {
    chain->rows = rc.T.transpose();
    chain->col_K = rc.T;
    chain->col_C = cq * rc.P + cv * rc.T;
    chain->col_M = cq * rc.Q + cv * rc.S + ca * rc.T;
  }
}

BlockState slot_state(const BlockState& b, SlotKind kind, const Mat3& offset) {
  if (kind != SlotKind::rotation) return b;
  BlockState s = b;
  s.rot = b.rot * offset;
  s.vel = offset.transpose() * b.vel;
  s.acc = offset.transpose() * b.acc;
  return s;
}

void gather_slots(const ElementEntry& entry, const std::vector<BlockState>& blocks,
                  std::vector<SlotState<double>>& slots) {
  const auto kinds = entry.element->slots();
  slots.clear();
  for (std::size_t k = 0; k < kinds.size(); ++k)
    slots.push_back(slot_state(blocks[entry.slots[k].block], kinds[k], entry.slots[k].offset));
}

ElementRun gather_run(const Model& model, const std::vector<int>& ids, int first, int count,
                      const std::vector<BlockState>& blocks) {
  if (count < 1 || count > kMaxElementBatch) throw std::logic_error("gather_run: one to kMaxElementBatch elements");
  thread_local std::array<std::vector<SlotState<double>>, kMaxElementBatch> slots;
  ElementRun run;
  run.count = count;
  for (int k = 0; k < count; ++k) {
    const ElementEntry& entry = model.elements[ids[first + k]];
    gather_slots(entry, blocks, slots[k]);
    run.elements[k] = entry.element.get();
    run.states[k] = slots[k];
  }
  return run;
}

}  // namespace latticedyn
