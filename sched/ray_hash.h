// A lock-free, insert-only hash map of fixed capacity, for values that are a pure function
// of their key (the radiance sample of a line, a canonical ray tree): whoever computes a
// value first publishes it, later writers of the same key simply drop theirs, and a reader
// that finds a slot still being written computes the value itself. So nothing observable
// depends on which thread won, and no thread ever waits.
//
// Open addressing with linear probing over an array of 64-bit tags: a tag is claimed by one
// compare-and-swap (the key's hash, never 0) and published by a release store that adds
// where its value lies and sets the low bit. A probe sequence reads a few cache lines of
// tags, not a cache line per entry (a lookup that misses reads all max_probe of them).
// The entries themselves (key and value, 184 bytes for a line's sample) are not kept at
// their tag's place but one after another in claim order, in a block reserved whole and
// written only as entries are claimed: a table sized for a whole frame (48 MB at 640x480)
// then touches memory in proportion to what it holds. With entries at their tags' places,
// a cold frame's first few thousand lines, scattered by their hashes, touched every page of
// it, and on this project's VM the kernel's clearing of those pages took a third of
// teapot-s6's first frame. Where an entry lies depends on which thread claimed first; what
// any lookup returns does not.
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
    const std::uint64_t h = Hash{}(key), tag = tag_of(h);
    for (int p = 0; p < max_probe_; ++p) {
      const std::size_t i = (h + std::uint64_t(p)) & mask_;
      const std::uint64_t t = tags_[i].load(std::memory_order_acquire);
      if (t == 0) return nullptr;
      if ((t & 1) && same_hash(t, tag)) {
        const slot& s = slots_[place_of(t)];
        if (s.key == key) return &s.value;
      }
    }
    return nullptr;
  }

  // Publishes value for key unless the key is present or being written, or the probe
  // sequence is full. Returns the published value (this one or an earlier one) or null.
  const Value* insert(const Key& key, const Value& value) {
    const std::uint64_t h = Hash{}(key), tag = tag_of(h);
    for (int p = 0; p < max_probe_; ++p) {
      const std::size_t i = (h + std::uint64_t(p)) & mask_;
      std::uint64_t t = tags_[i].load(std::memory_order_acquire);
      if (t == 0 && tags_[i].compare_exchange_strong(t, tag, std::memory_order_acq_rel)) {
        // One entry per claimed tag, so the next place is always within the block.
        const std::size_t place = size_.fetch_add(1, std::memory_order_relaxed);
        slot* s = ::new (static_cast<void*>(&slots_[place])) slot{key, value};
        tags_[i].store(tag | (std::uint64_t(place) << 1) | 1, std::memory_order_release);
        return &s->value;
      }
      if (same_hash(t, tag)) {
        if (!(t & 1)) return nullptr;  // being written: give up
        const slot& s = slots_[place_of(t)];
        if (s.key == key) return &s.value;
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
    for (std::size_t i = 0; i <= mask_; ++i) {
      const std::uint64_t t = tags_[i].load(std::memory_order_acquire);
      if (t & 1) f(slots_[place_of(t)].value);
    }
  }

 private:
  // Never destroyed: keys and values must need no destructor.
  struct slot {
    Key key;
    Value value;
  };
  static_assert(std::is_trivially_destructible_v<Key> && std::is_trivially_destructible_v<Value>);
  static_assert(alignof(slot) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__);
  // At most 2^31 tags, so that an entry's place fits in bits 1-31 of its tag.
  static constexpr std::size_t most = std::size_t(1) << 31;
  static std::size_t round_up(std::size_t n) {
    std::size_t c = 16;
    while (c < n && c < most) c <<= 1;
    return c;
  }
  // A tag: the key's hash in bits 32-63 (bit 32 set, so a claimed tag is never 0), the place
  // of its entry in bits 1-31 once published, and bit 0 set when published. Where a tag is
  // probed from comes from the hash's low bits, so the two halves are used for different ends.
  static constexpr std::uint64_t hash_bits = ~std::uint64_t(0) << 32;
  static std::uint64_t tag_of(std::uint64_t h) { return (h | (std::uint64_t(1) << 32)) & hash_bits; }
  // `tag` is tag_of's: it holds the hash bits alone.
  static bool same_hash(std::uint64_t stored, std::uint64_t tag) { return (stored & hash_bits) == tag; }
  static std::size_t place_of(std::uint64_t stored) { return std::size_t((stored & 0xffffffffu) >> 1); }
  std::size_t mask_;
  int max_probe_;
  std::unique_ptr<std::atomic<std::uint64_t>[]> tags_;
  // The entries, in 2 MB blocks advised as huge pages (huge_pages.h), written from the front
  // as they are claimed.
  std::unique_ptr<void, huge_deleter> storage_;
  slot* slots_;
  std::atomic<std::size_t> size_{0};  // entries claimed, and the next entry's place
};

}  // namespace epsray
