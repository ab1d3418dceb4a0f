// Builds a Model and realises "shared" connections (the thesis's public computing nodes, 7.4.1):
// a shared spherical or fixed constraint merges DoF blocks instead of adding multipliers.
#pragma once

#include "assembly/model.hpp"

#include <optional>

namespace latticedyn {

class ModelBuilder {
 public:
  ModelBuilder();

  void set_title(std::string title) { model_.title = std::move(title); }
  void set_gravity(const Vec3& g) { model_.gravity = g; }

  int add_block(DofBlock block);
  /// bodies()[0] is the ground, created by the constructor.
  int add_body(std::string name, std::string type);
  int add_element(int body, std::shared_ptr<const Element> element, std::vector<SlotBinding> slots);
  /// A joint on a body, attached to blocks of that body (see Joint).
  int add_joint(int body, Joint joint);
  /// A joint on the ground: a fixed frame at `position` with orientation `frame`.
  int add_ground_joint(std::string name, const Vec3& position, const Mat3& frame);
  int add_drive(std::string name, Drive drive);
  /// With shared = true a spherical or fixed constraint is realised by node sharing; both joints
  /// must sit on their block's origin (zero offset) and coincide in the initial state.
  void add_constraint(Constraint c, bool shared);
  void add_load(NodalLoad load);
  void set_draw_sequence(int body, std::vector<int> joint_indices);

  const Model& peek() const { return model_; }
  /// Merges shared blocks, drops unused ones and returns the model. Throws ModelError.
  Model build();

 private:
  struct Share {
    Constraint constraint;
  };
  struct Parent {
    int block;
    Mat3 offset;  // R_child = R_parent * offset
  };
  std::pair<int, Mat3> find(int b);
  void merge_translation(int a, int b, const std::string& what);
  void merge_rotation(int a, int b, const Mat3& R_ab, const std::string& what);
  void apply_share(const Constraint& c);
  void validate_constraint(const Constraint& c) const;

  Model model_;
  std::vector<Share> shares_;
  std::vector<Parent> parent_;
};

}  // namespace latticedyn
