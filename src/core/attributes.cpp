#include "isoforge/core/attributes.hpp"

namespace isoforge {

std::string_view attribute_role_name(AttributeRole role) {
  switch (role) {
    case AttributeRole::Scalars: return "scalars";
    case AttributeRole::Vectors: return "vectors";
    case AttributeRole::Normals: return "normals";
    case AttributeRole::Tensors: return "tensors";
    case AttributeRole::TCoords: return "tcoords";
  }
  return "?";
}

DataArray& Attributes::add(DataArray array) {
  if (array.name().empty()) throw Error("Attributes: an array needs a name");
  if (DataArray* existing = find(array.name())) {
    *existing = std::move(array);
    return *existing;
  }
  arrays_.push_back(std::move(array));
  return arrays_.back();
}

DataArray& Attributes::add(DataArray array, AttributeRole role) {
  std::string name = array.name();
  add(std::move(array));
  set_active(role, name);
  return get(name);
}

std::string Attributes::names() const {
  std::string s;
  for (const DataArray& a : arrays_) s += (s.empty() ? "'" : ", '") + a.name() + "'";
  return s.empty() ? "none" : s;
}

const DataArray* Attributes::find(std::string_view name) const {
  for (const auto& a : arrays_) {
    if (a.name() == name) return &a;
  }
  return nullptr;
}

DataArray* Attributes::find(std::string_view name) {
  for (auto& a : arrays_) {
    if (a.name() == name) return &a;
  }
  return nullptr;
}

const DataArray& Attributes::get(std::string_view name) const {
  if (const DataArray* a = find(name)) return *a;
  throw Error("no array named '" + std::string(name) + "'");
}

DataArray& Attributes::get(std::string_view name) {
  if (DataArray* a = find(name)) return *a;
  throw Error("no array named '" + std::string(name) + "'");
}

bool Attributes::remove(std::string_view name) {
  for (auto it = arrays_.begin(); it != arrays_.end(); ++it) {
    if (it->name() == name) {
      for (auto& r : active_) {
        if (r == name) r.clear();
      }
      arrays_.erase(it);
      return true;
    }
  }
  return false;
}

void Attributes::clear() {
  arrays_.clear();
  for (auto& r : active_) r.clear();
}

void Attributes::set_active(AttributeRole role, std::string_view name) {
  if (!name.empty() && !has(name)) {
    throw Error("cannot make '" + std::string(name) + "' the active " +
                std::string(attribute_role_name(role)) + ": no such array");
  }
  active_[static_cast<std::size_t>(role)] = std::string(name);
}

const std::string& Attributes::active_name(AttributeRole role) const {
  return active_[static_cast<std::size_t>(role)];
}

const DataArray* Attributes::active(AttributeRole role) const {
  const auto& n = active_[static_cast<std::size_t>(role)];
  return n.empty() ? nullptr : find(n);
}

DataArray* Attributes::active(AttributeRole role) {
  const auto& n = active_[static_cast<std::size_t>(role)];
  return n.empty() ? nullptr : find(n);
}

void Attributes::validate(std::size_t tuples, std::string_view what) const {
  for (const auto& a : arrays_) {
    if (a.tuples() != tuples) {
      throw Error(std::string(what) + " array '" + a.name() + "' has " +
                  std::to_string(a.tuples()) + " tuples, expected " + std::to_string(tuples));
    }
  }
}

}  // namespace isoforge
