// SPDX-License-Identifier: GPL-3.0-or-later
// Big output arrays (a scanned cloud, a tree's branch mesh): numbers that are left unset when the array grows (the
// threads write every entry before anything reads it, so zeroing them would be a serial pass over the whole array and
// its page faults), held in memory from std::malloc that can be handed over: the VTK wrappers adopt these arrays as
// their output arrays (freed there with std::free) instead of copying them.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <new>
#include <type_traits>
#include <utility>

#include "plantmorph/memory/HugePages.h"

namespace plantmorph
{

/// `HugePages`: large arrays are asked for transparent huge pages (see Allocate). Off for arrays that are written
/// once and handed over (a tree's mesh): there the kernel's compaction for huge pages measured slower and erratic
/// (system time 0.25-1.2 s where plain pages took 0.35 s for 400 MB, 2026-11-29, loaded machine).
template <class T, bool HugePages = true>
class CloudArray
{
  static_assert(std::is_trivially_copyable<T>::value, "a cloud array holds plain numbers");

public:
  using value_type = T;
  using iterator = T*;
  using const_iterator = const T*;

  CloudArray() = default;
  CloudArray(std::initializer_list<T> values) { this->assign(values.begin(), values.end()); }
  CloudArray(const CloudArray& other) { this->assign(other.begin(), other.end()); }
  CloudArray(CloudArray&& other) noexcept { this->swap(other); }
  CloudArray& operator=(CloudArray other) noexcept
  {
    this->swap(other);
    return *this;
  }
  ~CloudArray() { std::free(this->values); }

  std::size_t size() const { return this->count; }
  std::size_t capacity() const { return this->room; }
  bool empty() const { return this->count == 0; }
  T* data() { return this->values; }
  const T* data() const { return this->values; }
  T* begin() { return this->values; }
  T* end() { return this->values + this->count; }
  const T* begin() const { return this->values; }
  const T* end() const { return this->values + this->count; }
  T& operator[](std::size_t i) { return this->values[i]; }
  const T& operator[](std::size_t i) const { return this->values[i]; }

  /// Room for `n` numbers (the ones held are kept; new memory is untouched until written).
  void reserve(std::size_t n)
  {
    if (n <= this->room)
      return;
    T* grown = Allocate(n * sizeof(T));
    if (this->count > 0)
      std::memcpy(grown, this->values, this->count * sizeof(T));
    std::free(this->values);
    this->values = grown;
    this->room = n;
  }
  /// `n` numbers; those beyond the old size are unset.
  void resize(std::size_t n)
  {
    if (n > this->room)
      this->reserve(std::max(n, 2 * this->room));
    this->count = n;
  }
  /// The numbers [first, last) added at the end.
  void append(const T* first, const T* last)
  {
    const std::size_t old = this->count;
    this->resize(old + static_cast<std::size_t>(last - first));
    std::copy(first, last, this->values + old);
  }
  void assign(const T* first, const T* last)
  {
    this->count = 0;
    this->append(first, last);
  }
  /// One number added at the end (the room doubles when full, as std::vector's).
  void push_back(const T& value)
  {
    const T copy = value; // `value` may be one of the numbers held, moved by the growth
    this->resize(this->count + 1);
    this->values[this->count - 1] = copy;
  }
  template <class... Args>
  T& emplace_back(Args&&... args)
  {
    this->push_back(T(std::forward<Args>(args)...));
    return this->values[this->count - 1];
  }
  /// The numbers [first, last) (not from this array) inserted before `at`; returns where the first one went.
  T* insert(const T* at, const T* first, const T* last)
  {
    const std::size_t offset = static_cast<std::size_t>(at - this->values);
    const std::size_t n = static_cast<std::size_t>(last - first);
    const std::size_t old = this->count;
    if (n == 0)
      return this->values + offset;
    this->resize(old + n);
    std::memmove(this->values + offset + n, this->values + offset, (old - offset) * sizeof(T));
    std::copy(first, last, this->values + offset);
    return this->values + offset;
  }
  T* insert(const T* at, std::initializer_list<T> values) { return this->insert(at, values.begin(), values.end()); }
  /// No number left; the memory is kept.
  void clear() { this->count = 0; }
  T& back() { return this->values[this->count - 1]; }
  const T& back() const { return this->values[this->count - 1]; }
  /// Hands the memory over (to be freed with std::free); the array is left empty. nullptr when it holds nothing.
  T* Release()
  {
    T* held = this->count > 0 ? this->values : nullptr;
    if (!held)
      std::free(this->values);
    this->values = nullptr;
    this->count = this->room = 0;
    return held;
  }
  void swap(CloudArray& other) noexcept
  {
    std::swap(this->values, other.values);
    std::swap(this->count, other.count);
    std::swap(this->room, other.room);
  }
  friend bool operator==(const CloudArray& a, const CloudArray& b)
  {
    return a.count == b.count && std::equal(a.begin(), a.end(), b.begin());
  }

private:
  /// Memory for `bytes` (freed with std::free). Arrays of 4 MiB or more go on transparent huge pages, in whole
  /// pages (AllocateOnHugePages): a cloud of 10^7 points is written into fresh memory on every run, and its page
  /// faults, one per 4 KiB, were a tenth of the filter's time.
  static T* Allocate(std::size_t bytes)
  {
    if (HugePages && WorthHugePages(bytes))
      return static_cast<T*>(AllocateOnHugePages(bytes));
    void* memory = std::malloc(bytes);
    if (!memory)
      throw std::bad_alloc();
    return static_cast<T*>(memory);
  }

  T* values = nullptr;
  std::size_t count = 0;
  std::size_t room = 0;
};

} // namespace plantmorph
