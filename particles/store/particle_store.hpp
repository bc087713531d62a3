// One particle store for the particle models (dem, dpm): a structure of arrays
// with named attributes. The attributes every model has (id, species,
// position, velocity, angular velocity, radius, mass, inertia, force) are the
// ParticleArrays the drivers read; a model adds its own (dem: torque and the
// hydrodynamic force and torque; dpm: diameter, density, impulse, fluid sample,
// fluctuation). Every operation that moves particles (compaction, sorting, the
// rows a rank sends to another and receives) goes over all attributes, so a
// model cannot forget one. Reference variants keep their own plain storage.
#pragma once

#include <cstddef>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "particles/particles_interface.hpp"

namespace coflow::particles::store {

// What an attribute travels with: a particle moving to another rank
// (migrate), a copy of it sent to a neighbour for its contacts (ghost), both,
// or neither (it starts value-initialised on the receiving rank).
enum Travel : unsigned { stays = 0u, migrates = 1u, ghosts = 2u, always = 3u };

// How an entry of type T is written into doubles and read back: arithmetic
// types by conversion (ids below 2^53 are exact); a model's own struct
// specialises Codec with `doubles`, put and get.
template <class T, class = void>
struct Codec {
  static_assert(std::is_arithmetic_v<T>, "specialise store::Codec for this attribute type");
  static constexpr std::size_t doubles = 1;
  static void put(const T& v, double* out) { out[0] = static_cast<double>(v); }
  static T get(const double* in) { return static_cast<T>(in[0]); }
};

class Column {
 public:
  Column(std::string name, std::size_t width, Travel travel) : name_(std::move(name)), width_(width), travel_(travel) {}
  virtual ~Column() = default;
  const std::string& name() const { return name_; }
  bool travels(Travel with) const { return (travel_ & with) != 0u; }
  virtual std::size_t doubles() const = 0;  // per particle
  virtual std::size_t rows() const = 0;
  virtual void pack(std::size_t i, double* out) const = 0;
  virtual void unpack(const double* in) = 0;  // appends a row
  virtual void append_default() = 0;
  virtual void keep(const std::vector<char>& mask) = 0;       // stable compaction
  virtual void permute(const std::vector<std::size_t>& order) = 0;  // row r <- row order[r]

 protected:
  std::string name_;
  std::size_t width_;
  Travel travel_;
};

template <class T>
class TypedColumn final : public Column {
 public:
  TypedColumn(std::string name, std::size_t width, Travel travel, std::vector<T>& data)
      : Column(std::move(name), width, travel), data_(data) {}
  std::size_t doubles() const override { return width_ * Codec<T>::doubles; }
  std::size_t rows() const override { return data_.size() / width_; }
  void pack(std::size_t i, double* out) const override {
    for (std::size_t c = 0; c < width_; ++c) Codec<T>::put(data_[width_ * i + c], out + c * Codec<T>::doubles);
  }
  void unpack(const double* in) override {
    for (std::size_t c = 0; c < width_; ++c) data_.push_back(Codec<T>::get(in + c * Codec<T>::doubles));
  }
  void append_default() override { data_.resize(data_.size() + width_, T{}); }
  void keep(const std::vector<char>& mask) override {
    std::size_t k = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
      if (!mask[i]) continue;
      if (k != i)
        for (std::size_t c = 0; c < width_; ++c) data_[width_ * k + c] = data_[width_ * i + c];
      ++k;
    }
    data_.resize(width_ * k);
  }
  void permute(const std::vector<std::size_t>& order) override {
    const std::vector<T> copy = data_;
    for (std::size_t r = 0; r < order.size(); ++r)
      for (std::size_t c = 0; c < width_; ++c) data_[width_ * r + c] = copy[width_ * order[r] + c];
  }

 private:
  std::vector<T>& data_;
};

// The store is a table of named columns over the model's own vectors: the
// model keeps them as plain members (its hot loops read them directly, with no
// indirection) and registers each once.
class ParticleStore {
 public:
  // The common attributes, `arrays`, must outlive the store.
  explicit ParticleStore(ParticleArrays& arrays);
  ParticleStore(const ParticleStore&) = delete;
  ParticleStore& operator=(const ParticleStore&) = delete;

  ParticleArrays& arrays() { return arrays_; }
  const ParticleArrays& arrays() const { return arrays_; }
  std::size_t size() const { return arrays_.size(); }

  // A model's attribute: `width` entries of T per particle in `data` (which
  // must outlive the store).
  template <class T>
  void add(const std::string& name, std::size_t width, Travel travel, std::vector<T>& data) {
    columns_.push_back(std::make_unique<TypedColumn<T>>(name, width, travel, data));
  }

  // Doubles of one row holding the attributes that travel `with`.
  std::size_t row_doubles(Travel with) const;
  // Appends particle i's travelling attributes to `out`.
  void pack(std::size_t i, Travel with, std::vector<double>& out) const;
  // Appends one particle from a row written by pack(·, with, ·); the other
  // attributes start value-initialised.
  void unpack(const double* row, Travel with);
  // Appends one particle with every attribute value-initialised; its index.
  std::size_t append();
  // Appends every row of `rows` (a whole number of rows).
  void unpack_all(const std::vector<double>& rows, Travel with);
  // Keeps the particles flagged in `mask`, in order.
  void keep(const std::vector<char>& mask);
  // Orders the particles by id.
  void sort_by_id();
  // Throws, naming the attribute, if one holds another particle count.
  void check_sizes() const;

 private:
  ParticleArrays& arrays_;
  std::vector<std::unique_ptr<Column>> columns_;
};

}  // namespace coflow::particles::store
