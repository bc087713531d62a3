// Large arrays for hot loops: 2 MiB aligned and advised to use transparent huge
// pages, so that kernels streaming many arrays at once (19 populations, read and
// written) do not thrash the TLB with 4 KiB pages.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <utility>
#include <vector>

namespace coflow {

template <class T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr std::size_t alignment = std::size_t(2) << 20;

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}

  T* allocate(std::size_t n) {
    const std::size_t bytes = ((n * sizeof(T) + alignment - 1) / alignment) * alignment;
    void* p = std::aligned_alloc(alignment, bytes);
    if (!p) throw std::bad_alloc();
    ::madvise(p, bytes, MADV_HUGEPAGE);  // advice only: ignored where unsupported
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t) { std::free(p); }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const { return true; }
};

template <class T>
using HugeVector = std::vector<T, HugePageAllocator<T>>;

// `count` arrays of `n` values, array q starting `stride` values after array
// q - 1 (stride >= n), zero-initialised. The whole count x stride range is
// reserved as address space only; the arrays' own pages are made usable (and
// only they count against memory), advised to use transparent huge pages. A
// large stride fixed at compile time lets a kernel reach every array from a few
// base registers with constant displacements (lbm::SpacedRef).
template <class T>
class StridedArrays {
 public:
  StridedArrays() = default;
  StridedArrays(int count, std::size_t stride, std::size_t n) : stride_(stride) {
    constexpr std::size_t huge = std::size_t(2) << 20, page = 4096;
    bytes_ = count * stride * sizeof(T) + huge;
    void* p = ::mmap(nullptr, bytes_, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    base_ = p;
    const auto at = reinterpret_cast<std::uintptr_t>(p);
    data_ = reinterpret_cast<T*>((at + huge - 1) / huge * huge);
    for (int q = 0; q < count; ++q) {
      const auto lo = reinterpret_cast<std::uintptr_t>(data_ + q * stride) / page * page;
      const auto hi = (reinterpret_cast<std::uintptr_t>(data_ + q * stride + n) + page - 1) / page * page;
      void* first = reinterpret_cast<void*>(lo);
      if (::mprotect(first, hi - lo, PROT_READ | PROT_WRITE) != 0) {
        release();
        throw std::bad_alloc();
      }
      ::madvise(first, hi - lo, MADV_HUGEPAGE);  // advice only
    }
  }
  StridedArrays(const StridedArrays&) = delete;
  StridedArrays& operator=(const StridedArrays&) = delete;
  StridedArrays(StridedArrays&& o) noexcept { swap(o); }
  StridedArrays& operator=(StridedArrays&& o) noexcept {
    StridedArrays(std::move(o)).swap(*this);
    return *this;
  }
  ~StridedArrays() { release(); }

  void swap(StridedArrays& o) noexcept {
    std::swap(base_, o.base_);
    std::swap(bytes_, o.bytes_);
    std::swap(data_, o.data_);
    std::swap(stride_, o.stride_);
  }
  friend void swap(StridedArrays& a, StridedArrays& b) noexcept { a.swap(b); }

  T* data() { return data_; }
  const T* data() const { return data_; }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }
  std::size_t stride() const { return stride_; }

 private:
  void release() {
    if (base_) ::munmap(base_, bytes_);
    base_ = nullptr;
    data_ = nullptr;
  }
  void* base_ = nullptr;
  std::size_t bytes_ = 0;
  T* data_ = nullptr;
  std::size_t stride_ = 0;
};

}  // namespace coflow
