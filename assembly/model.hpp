// The multibody model as plain data: DoF blocks (the thesis's computing nodes), elements bound to
// blocks, joints (frames fixed on a block, 4.2), constraints (4.4), nodal loads (4.3), drives.
#pragma once

#include "core/drive.hpp"
#include "core/types.hpp"
#include "elements/element.hpp"

#include <memory>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace latticedyn {

/// A group of 3 (translation, rotation) or 1 (scalar) generalized coordinates. A rotation block's
/// coordinate is the rotation vector phi relative to its reference orientation:
/// R = orientation0 * exp(skew(phi)); phi = 0 initially. Fixed blocks carry no DoFs: the ground,
/// and nodes tied to the ground by a shared connection.
struct DofBlock {
  SlotKind kind = SlotKind::translation;
  bool fixed = false;
  Vec3 position0 = Vec3::Zero();     ///< translation: r; vector: its value; scalar: position0(0)
  Mat3 orientation0 = Mat3::Identity();
  Vec3 velocity0 = Vec3::Zero();     ///< translation: r_dot; rotation: body omega; scalar: (0)
  std::string label;                 ///< where it comes from, for messages ("boom.end2")
  /// Its equations are first order in it (a hydraulic pressure): the rate is not an initial
  /// condition but follows from the state (consistent_first_order_rates).
  bool first_order = false;
  /// Fixed, yet moving at velocity0 (in the slot's velocity variables): another solver's state held
  /// over a coupling step (a co-simulation partner's motion). Other fixed blocks are at rest.
  bool held = false;
  int size() const { return slot_size(kind); }

  static DofBlock translation(const Vec3& position, const Vec3& velocity, std::string label, bool fixed = false) {
    return DofBlock{SlotKind::translation, fixed, position, Mat3::Identity(), velocity, std::move(label), false, false};
  }
  static DofBlock vector(const Vec3& value, const Vec3& rate, std::string label, bool fixed = false) {
    return DofBlock{SlotKind::vector, fixed, value, Mat3::Identity(), rate, std::move(label), false, false};
  }
  static DofBlock scalar(double value, double rate, std::string label, bool fixed = false) {
    return DofBlock{SlotKind::scalar, fixed, Vec3(value, 0, 0), Mat3::Identity(), Vec3(rate, 0, 0), std::move(label), false, false};
  }
  static DofBlock rotation(const Mat3& orientation, const Vec3& omega, std::string label, bool fixed = false) {
    return DofBlock{SlotKind::rotation, fixed, Vec3::Zero(), orientation, omega, std::move(label), false, false};
  }
};

/// Binds an element slot to a block. For rotation slots the element's frame is the block frame
/// times `offset`, so elements meeting at an angle can share one node.
struct SlotBinding {
  int block = -1;
  Mat3 offset = Mat3::Identity();
};

struct ElementEntry {
  std::shared_ptr<const Element> element;
  std::vector<SlotBinding> slots;
  int body = -1;
};

/// A joint (4.2): a frame with constant position `offset` and orientation `frame` relative to a
/// block pair. A joint on a node without orientation (a strut tie end) has rotation_block = -1:
/// its orientation is the constant `frame` and only spherical constraints and forces attach.
struct Joint {
  std::string name;  ///< "body.joint"
  int body = -1;
  int translation_block = -1;
  int rotation_block = -1;
  Vec3 offset = Vec3::Zero();
  Mat3 frame = Mat3::Identity();
};

enum class ConstraintType { fixed, revolute, prismatic, spherical };

const char* to_string(ConstraintType t);

/// A constraint between two joints (4.4), enforced with Lagrange multipliers. Revolute and
/// prismatic act about/along `axis` (0, 1, 2 = x, y, z) of joint 1; with a drive they also
/// prescribe the relative angle (rad) or displacement (m) of joint 2 to joint 1 (7.4.2).
struct Constraint {
  std::string name;
  ConstraintType type = ConstraintType::spherical;
  int axis = 2;
  int joint1 = -1, joint2 = -1;
  int drive = -1;
  int rows() const;
};

enum class LoadFrame { inertial, body };

/// Force and moment on a joint (4.3, 4.9): given in the inertial frame or in the joint's own
/// (moving) frame; scaled by a drive when one is named, else constant.
struct NodalLoad {
  std::string name;
  int joint = -1;
  Vec3 force = Vec3::Zero();
  LoadFrame force_frame = LoadFrame::inertial;
  Vec3 moment = Vec3::Zero();
  LoadFrame moment_frame = LoadFrame::inertial;
  int drive = -1;
};

struct Body {
  std::string name;
  std::string type;
  std::vector<int> elements;
  std::vector<int> joints;
  /// Joints drawn as a polyline for rigid bodies (thesis Table D-16 "sequence"), indices into
  /// `joints`; empty draws a star from the first joint.
  std::vector<int> draw_sequence;
};

/// Names to indexes in a vector of named things, by hash: lookups in constant time while a model
/// of a million joints is built. Rebuilt from the vector when it has fallen behind (a model whose
/// vectors were filled by hand).
class NameIndex {
 public:
  void insert(const std::string& name, int index) { map_.emplace(name, index); }
  template <class Named>
  int find(const std::vector<Named>& items, const std::string& name) const {
    if (map_.size() != items.size()) {
      map_.clear();
      for (std::size_t i = 0; i < items.size(); ++i) map_.emplace(items[i].name, static_cast<int>(i));
    }
    const auto it = map_.find(name);
    return it == map_.end() ? -1 : it->second;
  }

 private:
  mutable std::unordered_map<std::string, int> map_;
};

struct Model {
  std::string title;
  Vec3 gravity = Vec3::Zero();
  std::vector<DofBlock> blocks;
  std::vector<ElementEntry> elements;
  std::vector<Body> bodies;  ///< bodies[0] is the ground
  std::vector<Joint> joints;
  std::vector<Constraint> constraints;
  std::vector<NodalLoad> loads;
  std::vector<Drive> drives;
  std::vector<std::string> drive_names;

  NameIndex body_index, joint_index;  ///< ModelBuilder keeps them as it adds bodies and joints

  int find_body(const std::string& name) const { return body_index.find(bodies, name); }   ///< -1 if absent
  int find_joint(const std::string& name) const { return joint_index.find(joints, name); }  ///< by "body.joint"
  int num_free_dofs() const;
  int num_multipliers() const;
};

/// Thrown for a model that cannot be assembled (inconsistent sharing, bad constraint on a node
/// without orientation, ...); the message names the constraint or body.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace latticedyn
