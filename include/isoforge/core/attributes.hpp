#pragma once
/// \file
/// `Attributes`: the ordered, named arrays attached to points, cells or a whole dataset, with
/// the active scalars/vectors/normals/tensors/tcoords roles of the chapter's data model.

#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "isoforge/core/data_array.hpp"

namespace isoforge {

/// The roles an array can play (at most one active array per role).
enum class AttributeRole : std::uint8_t { Scalars, Vectors, Normals, Tensors, TCoords };
inline constexpr std::size_t kAttributeRoleCount = 5;
[[nodiscard]] std::string_view attribute_role_name(AttributeRole role);

/// Ordered collection of uniquely named `DataArray`s.
///
/// For point and cell data every array must have one tuple per point/cell; the dataset checks
/// this with `validate`. Field data (per dataset) has no such constraint.
class Attributes {
 public:
  /// Adds `array`, replacing an array of the same name (which keeps its position and roles).
  /// Returns a reference to the stored array. \throw Error if the name is empty.
  DataArray& add(DataArray array);
  /// Adds and makes it the active array for `role`.
  DataArray& add(DataArray array, AttributeRole role);

  [[nodiscard]] bool has(std::string_view name) const { return find(name) != nullptr; }
  [[nodiscard]] const DataArray* find(std::string_view name) const;
  [[nodiscard]] DataArray* find(std::string_view name);
  /// \throw Error naming the array if it does not exist.
  [[nodiscard]] const DataArray& get(std::string_view name) const;
  [[nodiscard]] DataArray& get(std::string_view name);
  /// The names quoted and comma separated ("'a', 'b'"), or "none": for error messages.
  [[nodiscard]] std::string names() const;
  /// Removes the named array (and its roles); returns whether it existed.
  bool remove(std::string_view name);
  void clear();

  /// Makes `name` the active array for `role` ("" clears the role).
  /// \throw Error if no array has that name.
  void set_active(AttributeRole role, std::string_view name);
  /// Name of the active array for `role`, "" if none.
  [[nodiscard]] const std::string& active_name(AttributeRole role) const;
  [[nodiscard]] const DataArray* active(AttributeRole role) const;
  [[nodiscard]] DataArray* active(AttributeRole role);
  [[nodiscard]] const DataArray* scalars() const { return active(AttributeRole::Scalars); }
  [[nodiscard]] const DataArray* vectors() const { return active(AttributeRole::Vectors); }
  [[nodiscard]] const DataArray* normals() const { return active(AttributeRole::Normals); }
  [[nodiscard]] const DataArray* tensors() const { return active(AttributeRole::Tensors); }
  [[nodiscard]] const DataArray* tcoords() const { return active(AttributeRole::TCoords); }

  [[nodiscard]] std::size_t size() const { return arrays_.size(); }
  [[nodiscard]] bool empty() const { return arrays_.empty(); }
  [[nodiscard]] const DataArray& operator[](std::size_t i) const { return arrays_[i]; }
  [[nodiscard]] DataArray& operator[](std::size_t i) { return arrays_[i]; }
  [[nodiscard]] auto begin() const { return arrays_.begin(); }
  [[nodiscard]] auto end() const { return arrays_.end(); }
  [[nodiscard]] auto begin() { return arrays_.begin(); }
  [[nodiscard]] auto end() { return arrays_.end(); }

  /// Checks that every array has exactly `tuples` tuples.
  /// \throw Error naming `what` ("point data", "cell data") and the offending array.
  void validate(std::size_t tuples, std::string_view what) const;

  friend bool operator==(const Attributes&, const Attributes&) = default;

 private:
  std::vector<DataArray> arrays_;
  std::array<std::string, kAttributeRoleCount> active_;
};

}  // namespace isoforge
