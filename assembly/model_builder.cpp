// Model construction and node sharing by union-find over DoF blocks, where each link carries the
// constant rotation between a merged frame and its representative.
#include "assembly/model_builder.hpp"

#include "core/rotation.hpp"

#include <sstream>

namespace latticedyn {

namespace {
constexpr double kPositionTolerance = 1e-6;  // relative to 1 + |r|
constexpr double kAngleTolerance = 1e-6;     // rad

std::string fmt(const Vec3& v) {
  std::ostringstream os;
  os << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return os.str();
}
}  // namespace

ModelBuilder::ModelBuilder() { model_.bodies.push_back(Body{"ground", "ground", {}, {}, {}}); }

int ModelBuilder::add_block(DofBlock block) {
  model_.blocks.push_back(std::move(block));
  const int id = static_cast<int>(model_.blocks.size()) - 1;
  parent_.push_back({id, Mat3::Identity()});
  return id;
}

int ModelBuilder::add_body(std::string name, std::string type) {
  if (model_.find_body(name) >= 0) throw ModelError("body '" + name + "' is defined twice");
  model_.body_index.insert(name, static_cast<int>(model_.bodies.size()));
  model_.bodies.push_back(Body{std::move(name), std::move(type), {}, {}, {}});
  return static_cast<int>(model_.bodies.size()) - 1;
}

int ModelBuilder::add_element(int body, std::shared_ptr<const Element> element,
                              std::vector<SlotBinding> slots) {
  const auto kinds = element->slots();
  if (kinds.size() != slots.size()) throw ModelError("element slot count mismatch");
  for (std::size_t k = 0; k < kinds.size(); ++k)
    if (model_.blocks.at(slots[k].block).kind != kinds[k])
      throw ModelError("element slot bound to a block of the wrong kind");
  model_.elements.push_back(ElementEntry{std::move(element), std::move(slots), body});
  const int id = static_cast<int>(model_.elements.size()) - 1;
  model_.bodies.at(body).elements.push_back(id);
  return id;
}

int ModelBuilder::add_joint(int body, Joint joint) {
  joint.body = body;
  if (joint.rotation_block < 0 && joint.offset.norm() > 0)
    throw ModelError("joint '" + joint.name + "' has an offset on a node without orientation");
  if (model_.find_joint(joint.name) >= 0) throw ModelError("joint '" + joint.name + "' is defined twice");
  model_.joint_index.insert(joint.name, static_cast<int>(model_.joints.size()));
  model_.joints.push_back(std::move(joint));
  const int id = static_cast<int>(model_.joints.size()) - 1;
  model_.bodies.at(body).joints.push_back(id);
  return id;
}

int ModelBuilder::add_ground_joint(std::string name, const Vec3& position, const Mat3& frame) {
  Joint j;
  j.translation_block = add_block(DofBlock::translation(position, Vec3::Zero(), name, true));
  j.rotation_block = add_block(DofBlock::rotation(frame, Vec3::Zero(), name, true));
  j.name = std::move(name);
  return add_joint(0, std::move(j));
}

int ModelBuilder::add_drive(std::string name, Drive drive) {
  for (const auto& n : model_.drive_names)
    if (n == name) throw ModelError("drive '" + name + "' is defined twice");
  model_.drive_names.push_back(std::move(name));
  model_.drives.push_back(std::move(drive));
  return static_cast<int>(model_.drives.size()) - 1;
}

void ModelBuilder::add_constraint(Constraint c, bool shared) {
  validate_constraint(c);
  if (shared) {
    if (c.type != ConstraintType::spherical && c.type != ConstraintType::fixed)
      throw ModelError("constraint '" + c.name + "': only spherical and fixed connections can be shared (" +
                       to_string(c.type) + " keeps its multipliers)");
    if (c.drive >= 0) throw ModelError("constraint '" + c.name + "': a driven constraint cannot be shared");
    shares_.push_back({std::move(c)});
  } else {
    model_.constraints.push_back(std::move(c));
  }
}

void ModelBuilder::add_load(NodalLoad load) {
  const Joint& j = model_.joints.at(load.joint);
  if (j.rotation_block < 0 && load.moment.norm() > 0)
    throw ModelError("load '" + load.name + "': joint '" + j.name +
                     "' has no orientation (strut tie end), it cannot take a moment");
  if (j.rotation_block < 0 && load.force_frame == LoadFrame::body && load.force.norm() > 0)
    throw ModelError("load '" + load.name + "': joint '" + j.name +
                     "' has no orientation (strut tie end); give its force in the inertial frame");
  model_.loads.push_back(std::move(load));
}

void ModelBuilder::set_draw_sequence(int body, std::vector<int> joint_indices) {
  model_.bodies.at(body).draw_sequence = std::move(joint_indices);
}

void ModelBuilder::validate_constraint(const Constraint& c) const {
  const int nj = static_cast<int>(model_.joints.size());
  if (c.joint1 < 0 || c.joint1 >= nj || c.joint2 < 0 || c.joint2 >= nj)
    throw ModelError("constraint '" + c.name + "' refers to a joint that does not exist");
  if (c.joint1 == c.joint2) throw ModelError("constraint '" + c.name + "' connects a joint to itself");
  if (c.axis < 0 || c.axis > 2) throw ModelError("constraint '" + c.name + "' has an axis other than x, y, z");
  if (c.drive >= 0 && c.type != ConstraintType::revolute && c.type != ConstraintType::prismatic)
    throw ModelError("constraint '" + c.name + "': only revolute and prismatic constraints take a drive");
  if (c.type != ConstraintType::spherical) {
    for (int j : {c.joint1, c.joint2})
      if (model_.joints[j].rotation_block < 0)
        throw ModelError("constraint '" + c.name + "': joint '" + model_.joints[j].name +
                         "' has no orientation (strut tie end); only a spherical constraint can attach to it");
  }
}

std::pair<int, Mat3> ModelBuilder::find(int b) {
  if (parent_[b].block == b) return {b, Mat3::Identity()};
  auto [root, O] = find(parent_[b].block);
  parent_[b] = {root, O * parent_[b].offset};  // path compression keeps the composed offset
  return {root, parent_[b].offset};
}

void ModelBuilder::merge_translation(int a, int b, const std::string& what) {
  const int ra = find(a).first, rb = find(b).first;
  if (ra == rb) return;
  const Vec3& pa = model_.blocks[ra].position0;
  const Vec3& pb = model_.blocks[rb].position0;
  if ((pa - pb).norm() > kPositionTolerance * (1 + pa.norm()))
    throw ModelError(what + ": the joints are " + std::to_string((pa - pb).norm()) +
                     " m apart in the initial state, at " + fmt(pa) + " and " + fmt(pb) +
                     "; a shared connection needs coincident joints");
  // One node moves with one velocity: the merged blocks must start with the same one (a fixed
  // block has none).
  const Vec3 va = model_.blocks[ra].fixed ? Vec3::Zero() : model_.blocks[ra].velocity0;
  const Vec3 vb = model_.blocks[rb].fixed ? Vec3::Zero() : model_.blocks[rb].velocity0;
  if ((va - vb).norm() > kPositionTolerance * (1 + va.norm()))
    throw ModelError(what + ": the joints start with different velocities " + fmt(va) + " and " + fmt(vb) +
                     "; a shared node has one velocity");
  if (model_.blocks[rb].fixed && !model_.blocks[ra].fixed)
    parent_[ra] = {rb, Mat3::Identity()};
  else
    parent_[rb] = {ra, Mat3::Identity()};
}

void ModelBuilder::merge_rotation(int a, int b, const Mat3& R_ab, const std::string& what) {
  auto [ra, Oa] = find(a);
  auto [rb, Ob] = find(b);
  // Frames: R_a = R_ra Oa, R_b = R_rb Ob, and the connection demands R_b = R_a R_ab.
  const Mat3 link = Oa * R_ab * Ob.transpose();  // R_rb = R_ra * link
  const Mat3 Rra = model_.blocks[ra].orientation0, Rrb = model_.blocks[rb].orientation0;
  const double mismatch = rotation_vector(Rrb.transpose() * Rra * link).norm();
  if (mismatch > kAngleTolerance)
    throw ModelError(what + ": the joint frames differ by " + std::to_string(mismatch * 180 / 3.141592653589793) +
                     " degrees in the initial state; a shared fixed connection needs aligned joint frames");
  if (ra == rb) return;
  // Same angular velocity in space (body-frame omega times the frame).
  auto spin = [&](int r) -> Vec3 {
    const DofBlock& blk = model_.blocks[r];
    return blk.fixed ? Vec3::Zero() : Vec3(blk.orientation0 * blk.velocity0);
  };
  if ((spin(ra) - spin(rb)).norm() > kPositionTolerance * (1 + spin(ra).norm()))
    throw ModelError(what + ": the joints start with different angular velocities " + fmt(spin(ra)) + " and " +
                     fmt(spin(rb)) + " (inertial frame); a shared fixed node has one");
  if (model_.blocks[rb].fixed && !model_.blocks[ra].fixed)
    parent_[ra] = {rb, link.transpose()};
  else
    parent_[rb] = {ra, link};
}

void ModelBuilder::apply_share(const Constraint& c) {
  const Joint& j1 = model_.joints[c.joint1];
  const Joint& j2 = model_.joints[c.joint2];
  const std::string what = "shared constraint '" + c.name + "'";
  for (const Joint* j : {&j1, &j2})
    if (j->offset.norm() > 0)
      throw ModelError(what + ": joint '" + j->name +
                       "' is off its node (offset != 0); only joints on a node can share it");
  merge_translation(j1.translation_block, j2.translation_block, what);
  if (c.type == ConstraintType::fixed) merge_rotation(j1.rotation_block, j2.rotation_block, j1.frame * j2.frame.transpose(), what);
}

Model ModelBuilder::build() {
  for (const auto& s : shares_) apply_share(s.constraint);

  // Representatives that anything refers to become the blocks of the built model.
  const int nb = static_cast<int>(model_.blocks.size());
  std::vector<int> new_id(nb, -1);
  std::vector<DofBlock> blocks;
  auto use = [&](int b) -> std::pair<int, Mat3> {
    auto [root, O] = find(b);
    if (new_id[root] < 0) {
      new_id[root] = static_cast<int>(blocks.size());
      blocks.push_back(model_.blocks[root]);
    }
    return {new_id[root], O};
  };
  for (auto& e : model_.elements)
    for (auto& s : e.slots) {
      auto [id, O] = use(s.block);
      s.block = id;
      s.offset = O * s.offset;
    }
  for (auto& j : model_.joints) {
    j.translation_block = use(j.translation_block).first;
    if (j.rotation_block >= 0) {
      auto [id, O] = use(j.rotation_block);
      j.rotation_block = id;
      j.frame = O * j.frame;
      j.offset = O * j.offset;
    }
  }
  model_.blocks = std::move(blocks);

  auto fixed_joint = [&](int j) {
    const Joint& jt = model_.joints[j];
    return model_.blocks[jt.translation_block].fixed &&
           (jt.rotation_block < 0 || model_.blocks[jt.rotation_block].fixed);
  };
  for (const auto& c : model_.constraints)
    if (fixed_joint(c.joint1) && fixed_joint(c.joint2))
      throw ModelError("constraint '" + c.name + "' connects two joints that are both fixed in space");

  Model out = std::move(model_);
  model_ = Model{};
  shares_.clear();
  parent_.clear();
  return out;
}

}  // namespace latticedyn
