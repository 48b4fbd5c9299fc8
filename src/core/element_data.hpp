// Per-element data in typed containers (geometry-central style): a VertexData<double> cannot be
// passed where a FaceData<double> is expected, even though both are indexed by uint32_t.
#pragma once

#include <cstdint>
#include <vector>

namespace isoquad {

inline constexpr uint32_t kInvalid = 0xFFFFFFFFu;

template <class Tag, class T>
class ElementData {
 public:
  ElementData() = default;
  explicit ElementData(std::size_t n, const T& value = T{}) : data_(n, value) {}
  explicit ElementData(std::vector<T> values) : data_(std::move(values)) {}

  decltype(auto) operator[](uint32_t i) { return data_[i]; }
  decltype(auto) operator[](uint32_t i) const { return data_[i]; }
  std::size_t size() const { return data_.size(); }
  auto begin() { return data_.begin(); }
  auto end() { return data_.end(); }
  auto begin() const { return data_.begin(); }
  auto end() const { return data_.end(); }
  const std::vector<T>& values() const { return data_; }
  std::vector<T>& values() { return data_; }

 private:
  std::vector<T> data_;
};

struct VertexTag {};
struct FaceTag {};
struct EdgeTag {};
struct HalfedgeTag {};

template <class T>
using VertexData = ElementData<VertexTag, T>;
template <class T>
using FaceData = ElementData<FaceTag, T>;
template <class T>
using EdgeData = ElementData<EdgeTag, T>;
template <class T>
using HalfedgeData = ElementData<HalfedgeTag, T>;

}  // namespace isoquad
