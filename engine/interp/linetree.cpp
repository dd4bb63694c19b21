#include "interp/linetree.h"

#include <algorithm>
#include <array>
#include <bit>
#include <functional>
#include <tuple>

namespace epsray {

lt_node::~lt_node() {
  delete[] kids.load(std::memory_order_relaxed);
  interpolant* ip = interp.load(std::memory_order_relaxed);
  if (ip && !ip->shared) delete ip;
}

const interpolant* failure_record(cell_reason r, std::uint8_t split, bool could_defer) {
  static const auto records = [] {
    std::array<std::array<std::array<interpolant, 2>, 16>, 5> all{};
    for (int i = 0; i < 5; ++i)
      for (int k = 0; k < 16; ++k)
        for (int d = 0; d < 2; ++d) {
          interpolant& ip = all[size_t(i)][size_t(k)][size_t(d)];
          ip.reason = cell_reason(i), ip.split = std::uint8_t(k), ip.shared = true, ip.could_defer = d != 0;
        }
    return all;
  }();
  return &records[size_t(r)][split & 15u][could_defer ? 1 : 0];
}

lt_node* subdivide(lt_node& n, std::uint8_t axes, std::atomic<std::size_t>* bytes) {
  lt_node* kids = n.kids.load(std::memory_order_acquire);
  if (kids) return kids;
  const int count = child_count(axes);
  lt_node* made = new lt_node[size_t(count)];
  for (int k = 0; k < count; ++k) {
    for (int i = 0, bit = 0; i < 4; ++i) {
      made[k].lo[i] = n.lo[i], made[k].hi[i] = n.hi[i];
      made[k].level[i] = n.level[i];
      if (!(axes >> i & 1)) continue;
      made[k].level[i] = std::uint8_t(n.level[i] + 1);
      made[k].depth = std::max(made[k].depth, made[k].level[i]);
      float mid = 0.5f * (n.lo[i] + n.hi[i]);
      (k >> bit & 1 ? made[k].lo[i] : made[k].hi[i]) = mid;
      ++bit;
    }
    made[k].parent_axes = axes;
  }
  if (n.kids.compare_exchange_strong(kids, made, std::memory_order_acq_rel)) {
    if (bytes) bytes->fetch_add(size_t(count) * sizeof(lt_node), std::memory_order_relaxed);
    return made;
  }
  delete[] made;  // lost the race: the winner's children are identical
  return kids;
}

const interpolant* publish(lt_node& n, std::unique_ptr<interpolant> made, std::atomic<std::size_t>* bytes,
                           bool* won) {
  return republish(n, nullptr, std::move(made), bytes, won);
}

const interpolant* republish(lt_node& n, const interpolant* old, std::unique_ptr<interpolant> made,
                             std::atomic<std::size_t>* bytes, bool* won) {
  if (won) *won = false;
  interpolant* mine = made->reason == cell_reason::valid
                          ? made.get()
                          : const_cast<interpolant*>(failure_record(made->reason, made->split, made->could_defer));
  interpolant* expected = const_cast<interpolant*>(old);
  if (!n.interp.compare_exchange_strong(expected, mine, std::memory_order_acq_rel)) return expected;
  if (won) *won = true;
  if (mine == made.get()) {
    made.release();
    if (bytes) bytes->fetch_add(mine->bytes(), std::memory_order_relaxed);
  }
  return mine;
}

namespace {
// The unique-ray hash: room for about half a line per pixel (a cold 800x600 frame of the
// art room shares 133k lines), 2^12 to 2^18 of them, and at most a quarter of a memory
// budget: the largest power of two that fits, since the table rounds up.
std::size_t line_capacity(std::size_t budget, std::size_t pixels) {
  constexpr std::size_t least = std::size_t(1) << 12, most = std::size_t(1) << 18;
  std::size_t cap = pixels ? std::clamp(std::bit_ceil(pixels / 2), least, most) : most;
  if (budget) {
    const std::size_t slot = decltype(sample_cache::lines)::slot_bytes();
    cap = std::min(cap, std::bit_floor(std::clamp(budget / 4 / slot, least, most)));
  }
  return cap;
}
}  // namespace

linetree_set::linetree_set(const std::vector<bounds>& prim_bounds, size_t memory_budget, size_t pixels)
    : bounds_(prim_bounds), budget_(memory_budget),
      trees_(new std::array<std::atomic<linetree*>, 6>[prim_bounds.size()]), count_(prim_bounds.size()),
      samples_(line_capacity(memory_budget, pixels), memory_budget ? std::size_t(1) << 13 : std::size_t(1) << 16) {
  for (size_t i = 0; i < count_; ++i)
    for (auto& t : trees_[i]) t.store(nullptr, std::memory_order_relaxed);
  flat_.reserve(count_);
  for (const bounds& b : bounds_) flat_.push_back(std::int8_t(flat_axis(b)));
  gate.resize(count_);
}

linetree_set::~linetree_set() {
  for (size_t i = 0; i < count_; ++i)
    for (auto& t : trees_[i]) delete t.load(std::memory_order_relaxed);
}

light_cache* linetree_set::lights(const world& w) {
  if (!lights_) lights_ = std::make_unique<light_cache>(w);
  return lights_.get();
}

size_t linetree_set::light_bytes() const { return lights_ ? lights_->bytes() : 0; }

linetree& linetree_set::get(int prim, int fi) {
  std::atomic<linetree*>& slot = trees_[size_t(prim)][size_t(fi)];
  linetree* t = slot.load(std::memory_order_acquire);
  if (t) return *t;
  auto* made = new linetree;
  made->fp = make_facepair(bounds_[size_t(prim)], fi);
  for (int i = 0; i < 4; ++i) made->root.lo[i] = made->fp.lo[i], made->root.hi[i] = made->fp.hi[i];
  if (slot.compare_exchange_strong(t, made, std::memory_order_acq_rel)) {
    node_bytes_.fetch_add(sizeof(linetree), std::memory_order_relaxed);
    return *made;
  }
  delete made;
  return *t;
}

size_t linetree_set::bytes() const {
  return count_ * sizeof(std::array<std::atomic<linetree*>, 6>) + samples_.bytes() +
         node_bytes_.load(std::memory_order_relaxed);
}

size_t linetree_set::measured_bytes() const {
  size_t total = count_ * sizeof(std::array<std::atomic<linetree*>, 6>) + samples_.bytes();
  std::function<size_t(const lt_node&)> walk = [&](const lt_node& n) -> size_t {
    const interpolant* ip = n.interp.load(std::memory_order_acquire);
    size_t b = ip && !ip->shared ? ip->bytes() : 0;
    if (const lt_node* k = n.kids.load(std::memory_order_acquire)) {
      const int count = child_count(k[0].parent_axes);
      b += size_t(count) * sizeof(lt_node);
      for (int i = 0; i < count; ++i) b += walk(k[i]);
    }
    return b;
  };
  for (size_t i = 0; i < count_; ++i)
    for (const auto& t : trees_[i])
      if (const linetree* lt = t.load(std::memory_order_acquire)) total += sizeof(linetree) + walk(lt->root);
  return total;
}

size_t linetree_set::evict() {
  if (samples_.crowded()) samples_.clear();  // a cache of lines from frames ago, mostly
  if (budget_ == 0) return 0;
  size_t total = bytes();
  // Down to 7/8 of the budget: the next frame's new cells then fit under it, unless that
  // frame's working set alone is larger.
  const size_t target = budget_ - budget_ / 8;
  if (total <= target) return total;
  // The caches first: cheap to refill, and what is left is then a deterministic size (the
  // trees a cache holds depend on which thread traced which line first).
  total -= samples_.bytes();
  samples_.clear();
  total += samples_.bytes();
  if (total <= target) return total;

  // The largest subtrees nobody reached this frame, a node's children all together, found
  // in one pass, children before parents: a stale subtree replaces the stale ones found
  // inside it. visit returns the newest use and the bytes of n and all below it.
  struct unit {
    std::uint32_t newest;
    int prim, fp;
    lt_node* node;
    size_t bytes;
  };
  std::vector<unit> units;
  std::function<std::pair<std::uint32_t, size_t>(lt_node&, int, int)> visit =
      [&](lt_node& n, int prim, int fp) -> std::pair<std::uint32_t, size_t> {
    const std::uint32_t used = n.used.load(std::memory_order_relaxed);
    const interpolant* ip = n.interp.load(std::memory_order_relaxed);
    const size_t own = ip && !ip->shared ? ip->bytes() : 0;
    lt_node* k = n.kids.load(std::memory_order_relaxed);
    if (!k) return {used, own};
    const size_t inside = units.size();
    const int count = child_count(k[0].parent_axes);
    std::uint32_t below = 0;
    size_t b = size_t(count) * sizeof(lt_node);
    for (int i = 0; i < count; ++i) {
      auto [s, cb] = visit(k[i], prim, fp);
      below = std::max(below, s), b += cb;
    }
    if (below < frame_) {
      units.resize(inside);
      units.push_back({below, prim, fp, &n, b});
    }
    return {std::max(used, below), own + b};
  };
  for (size_t i = 0; i < count_; ++i)
    for (int f = 0; f < 6; ++f)
      if (linetree* lt = trees_[i][size_t(f)].load(std::memory_order_relaxed)) visit(lt->root, int(i), f);
  auto key = [](const unit& u) {
    const lt_node& n = *u.node;
    return std::make_tuple(u.newest, u.prim, u.fp, n.lo[0], n.lo[1], n.lo[2], n.lo[3], n.hi[0], n.hi[1], n.hi[2],
                           n.hi[3]);
  };
  std::sort(units.begin(), units.end(), [&](const unit& a, const unit& b) { return key(a) < key(b); });
  for (const unit& u : units) {
    if (total <= target) break;
    delete[] u.node->kids.exchange(nullptr, std::memory_order_relaxed);
    total -= u.bytes;
    node_bytes_.fetch_sub(u.bytes, std::memory_order_relaxed);
  }
  return total;
}

}  // namespace epsray
