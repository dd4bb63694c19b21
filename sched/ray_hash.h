// A lock-free, insert-only hash map of fixed capacity, for values that are a pure function
// of their key (the radiance sample of a line, a canonical ray tree): whoever computes a
// value first publishes it, later writers of the same key simply drop theirs, and a reader
// that finds a slot still being written computes the value itself. So nothing observable
// depends on which thread won, and no thread ever waits.
//
// Open addressing with linear probing; a slot is claimed by one compare-and-swap on its
// 64-bit tag (from the key's hash, never 0) and published by a release store of the tag
// with its low bit set. The tags live in an array of their own, so a probe sequence reads
// a few cache lines of tags, not a cache line per slot (a lookup that misses reads all
// max_probe of them). A slot is read only once its tag says it is published, so the slots'
// memory is left as allocated until then: a table sized for a whole frame (48 MB at
// 640x480) costs nothing where few lines are traced, where writing it all cost a short
// walk 3% of its time.
// Knows nothing of rendering.
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>

#include "sched/huge_pages.h"

namespace epsray {

template <class Key, class Value, class Hash>
class insert_only_map {
 public:
  // capacity is rounded up to a power of two; probes stop after `max_probe` slots.
  explicit insert_only_map(std::size_t capacity, int max_probe = 32)
      : mask_(round_up(capacity) - 1), max_probe_(max_probe), tags_(new std::atomic<std::uint64_t>[mask_ + 1]),
        storage_(take_huge((mask_ + 1) * sizeof(slot))), slots_(static_cast<slot*>(storage_.get())) {
    for (std::size_t i = 0; i <= mask_; ++i) tags_[i].store(0, std::memory_order_relaxed);
  }

  // The published value for key, or null.
  const Value* find(const Key& key) const {
    const std::uint64_t tag = tag_of(key);
    for (int p = 0; p < max_probe_; ++p) {
      const std::size_t i = (tag + std::uint64_t(p)) & mask_;
      const std::uint64_t t = tags_[i].load(std::memory_order_acquire);
      if (t == 0) return nullptr;
      if (t == (tag | 1) && slots_[i].key == key) return &slots_[i].value;
    }
    return nullptr;
  }

  // Publishes value for key unless the key is present or being written, or the probe
  // sequence is full. Returns the published value (this one or an earlier one) or null.
  const Value* insert(const Key& key, const Value& value) {
    const std::uint64_t tag = tag_of(key);
    for (int p = 0; p < max_probe_; ++p) {
      const std::size_t i = (tag + std::uint64_t(p)) & mask_;
      std::uint64_t t = tags_[i].load(std::memory_order_acquire);
      if (t == 0 && tags_[i].compare_exchange_strong(t, tag, std::memory_order_acq_rel)) {
        slot* s = ::new (static_cast<void*>(&slots_[i])) slot{key, value};
        tags_[i].store(tag | 1, std::memory_order_release);
        size_.fetch_add(1, std::memory_order_relaxed);
        return &s->value;
      }
      if ((t & ~std::uint64_t(1)) == tag) {
        if (!(t & 1)) return nullptr;  // being written: give up
        if (slots_[i].key == key) return &slots_[i].value;
      }
    }
    return nullptr;  // full around here: the caller keeps its value unshared
  }

  // Forgets every entry. Not concurrent: only while no thread uses the map.
  void clear() {
    for (std::size_t i = 0; i <= mask_; ++i) tags_[i].store(0, std::memory_order_relaxed);
    size_.store(0, std::memory_order_relaxed);
  }

  std::size_t size() const { return size_.load(std::memory_order_relaxed); }
  std::size_t capacity() const { return mask_ + 1; }
  std::size_t bytes() const { return capacity() * slot_bytes(); }
  static constexpr std::size_t slot_bytes() { return sizeof(slot) + sizeof(std::uint64_t); }

  // Every published value, for owners that must free what the values point to.
  template <class F>
  void for_each(F&& f) const {
    for (std::size_t i = 0; i <= mask_; ++i)
      if (tags_[i].load(std::memory_order_acquire) & 1) f(slots_[i].value);
  }

 private:
  // Never destroyed: keys and values must need no destructor.
  struct slot {
    Key key;
    Value value;
  };
  static_assert(std::is_trivially_destructible_v<Key> && std::is_trivially_destructible_v<Value>);
  static_assert(alignof(slot) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__);
  static std::size_t round_up(std::size_t n) {
    std::size_t c = 16;
    while (c < n) c <<= 1;
    return c;
  }
  // Bit 0 of a stored tag says the slot is published; bit 1 keeps a claimed tag nonzero.
  static std::uint64_t tag_of(const Key& k) { return (Hash{}(k) | 2) & ~std::uint64_t(1); }
  std::size_t mask_;
  int max_probe_;
  std::unique_ptr<std::atomic<std::uint64_t>[]> tags_;
  // The slots, constructed as they are claimed; in huge pages (huge_pages.h), since a
  // frame's lines scatter over all of it.
  std::unique_ptr<void, huge_deleter> storage_;
  slot* slots_;
  std::atomic<std::size_t> size_{0};
};

}  // namespace epsray
