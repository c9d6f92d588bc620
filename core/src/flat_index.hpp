#pragma once
// An open-addressing hash index from 64-bit keys to 32-bit slots, for the
// fast integration path's per-frame tables (pixel groups by end voxel, voxel
// bricks). Linear probing over a power-of-two table, no per-entry allocation,
// no erase; far cheaper per lookup than std::unordered_map for these sizes.
#include <algorithm>
#include <cstdint>
#include <vector>

namespace lom {

class FlatIndex {
 public:
  // Keys must differ from kEmpty (callers pack at most 49 bits).
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  explicit FlatIndex(size_t expected = 1024) { reset(expected); }

  void reset(size_t expected) {
    size_t capacity = 64;
    while (capacity < 2 * expected) capacity *= 2;
    entries_.assign(capacity, Entry{});
    shift_ = 64 - log2(capacity);
    size_ = 0;
  }

  // The table's memory, in bytes.
  [[nodiscard]] size_t memoryBytes() const { return entries_.capacity() * sizeof(Entry); }

  // Empties the table, keeping its capacity (for reuse from frame to frame).
  void clear() {
    std::fill(entries_.begin(), entries_.end(), Entry{});
    size_ = 0;
  }

  // The value stored for `key`; when absent, stores `value_if_new` and sets `inserted`.
  std::uint32_t findOrInsert(std::uint64_t key, std::uint32_t value_if_new, bool& inserted) {
    size_t slot = slotOf(key);
    const size_t mask = entries_.size() - 1;
    while (true) {
      const std::uint64_t k = entries_[slot].key;
      if (k == key) {
        inserted = false;
        return entries_[slot].value;
      }
      if (k == kEmpty) break;
      slot = (slot + 1) & mask;
    }
    inserted = true;
    if (2 * (size_ + 1) > entries_.size()) {
      grow();
      return insertNew(key, value_if_new);
    }
    entries_[slot] = {key, value_if_new};
    ++size_;
    return value_if_new;
  }

  // The value stored for `key`, or nullptr.
  [[nodiscard]] const std::uint32_t* find(std::uint64_t key) const {
    size_t slot = slotOf(key);
    const size_t mask = entries_.size() - 1;
    while (true) {
      const std::uint64_t k = entries_[slot].key;
      if (k == key) return &entries_[slot].value;
      if (k == kEmpty) return nullptr;
      slot = (slot + 1) & mask;
    }
  }

  // The multiplicative hash the table uses; its top bits are the best mixed.
  static std::uint64_t mix(std::uint64_t key) { return key * 0x9E3779B97F4A7C15ULL; }

 private:
  static int log2(size_t v) {
    int bits = 0;
    while ((size_t{1} << bits) < v) ++bits;
    return bits;
  }
  [[nodiscard]] size_t slotOf(std::uint64_t key) const {
    return static_cast<size_t>(mix(key) >> shift_);
  }
  std::uint32_t insertNew(std::uint64_t key, std::uint32_t value) {
    size_t slot = slotOf(key);
    const size_t mask = entries_.size() - 1;
    while (entries_[slot].key != kEmpty) slot = (slot + 1) & mask;
    entries_[slot] = {key, value};
    ++size_;
    return value;
  }
  void grow() {
    std::vector<Entry> entries;
    entries.swap(entries_);
    reset(entries.size());  // doubles: reset sizes the table for 2x the expected count
    for (const Entry& e : entries)
      if (e.key != kEmpty) insertNew(e.key, e.value);
  }

  struct Entry {  // key and value side by side: one cache line per probe
    std::uint64_t key = kEmpty;
    std::uint32_t value = 0;
  };
  std::vector<Entry> entries_;
  int shift_ = 58;
  size_t size_ = 0;
};

}  // namespace lom
