#include "interp/object_gate.h"

#include <algorithm>

#include "interp/interp_shade.h"

namespace epsray {

gate_tally& gate_tally::operator+=(const gate_tally& o) {
  fast += o.fast, span += o.span, interp += o.interp, saved += o.saved, own += o.own;
  traced += o.traced, traced_rays += o.traced_rays, builds += o.builds;
  return *this;
}

double gate_gain(const gate_tally& t, bool moving, const gate_weights& wt) {
  double gain = double(t.saved) - double(t.own);
  gain -= wt.fast * double(t.fast) + wt.span * double(t.span) + wt.interp * double(t.interp);
  gain -= wt.failed_lookup * double(t.traced);
  if (moving && t.builds) {
    // A corner line costs what a traced pixel of the object does.
    const double pixels = double(t.fast + t.span + t.interp + t.traced);
    const double per_line = pixels > 0 ? double(t.saved + t.traced_rays) / pixels : 1.0;
    gain -= 16 * wt.corner_share * per_line * double(t.builds);
  }
  return gain;
}

void gate_count(gate_tally& g, const pixel_result& r, std::uint64_t own, bool reprojecting) {
  if (r.cell.ip && r.path == pixel_path::interp && reprojecting) {
    ++g.fast, g.saved += r.cell.ip->tree_rays, g.own += own - std::min<std::uint64_t>(own, 1);  // no visibility ray
  } else if (r.cell.ip && r.path != pixel_path::base) {
    ++(r.path == pixel_path::fast ? g.fast : g.interp);
    g.saved += r.cell.ip->tree_rays, g.own += own;
  } else {
    ++g.traced, g.traced_rays += own;
  }
}

namespace {
// plain_gain: the cells kept on saved too little of a plain frame's rays.
bool saves_too_little(double gain, std::uint64_t rays) {
  return gain < plain_gain * (double(rays) + std::max(0.0, gain));
}
// allowance_share: the allowance bounded too few of the rays it could cast.
bool bounds_too_few(std::uint64_t bounded, std::uint64_t cast) {
  return double(bounded) < allowance_share * double(bounded + cast);
}
}  // namespace

void object_gate::resize(std::size_t prims) {
  off_until_.assign(prims, 0);
  strikes_.assign(prims, 0);
  off_pixels_.assign(prims, 0);
  sum_.assign(prims, gate_tally{});
  touched_.clear();
}

double object_gate::judge(const std::vector<gate_entry>& tallies, bool moving, const float* box_pixels, bool apply) {
  for (const gate_entry& e : tallies) {
    if (e.prim < 0 || std::size_t(e.prim) >= sum_.size()) continue;
    gate_tally& s = sum_[std::size_t(e.prim)];
    if (!(s.fast | s.span | s.interp | s.traced | s.builds)) touched_.push_back(e.prim);
    s += e.t;
  }
  double gain = 0;  // of the objects kept on
  for (int p : touched_) {
    gate_tally& s = sum_[std::size_t(p)];
    // Only a clear loss counts: half a ray a pixel (on the art-room walk at 800x600 any
    // loss at all turned off objects whose cells paid later, 1.097 of the time).
    const double pixels = double(s.fast + s.span + s.interp + s.traced);
    const double g = gate_gain(s, moving);
    if (!(g < -gate_margin * pixels)) {
      gain += g;
    } else if (apply) {
      const std::uint8_t k = strikes_[std::size_t(p)];
      off_until_[std::size_t(p)] = frame_ + (8u << std::min<unsigned>(k, 3));
      strikes_[std::size_t(p)] = std::uint8_t(std::min(k + 1, 255));
      off_pixels_[std::size_t(p)] = box_pixels ? box_pixels[p] : 0;
    }
    s = gate_tally{};
  }
  touched_.clear();
  return gain;
}

void object_gate::go_plain() {
  plain_left_ = 8u << std::min<unsigned>(plain_strikes_, 3);
  plain_strikes_ = std::uint8_t(std::min(plain_strikes_ + 1, 255));
}

void object_gate::update(const std::vector<gate_entry>& tallies, bool moving, const float* box_pixels,
                         std::uint64_t frame_rays) {
  if (!enabled()) return;
  ++frame_;  // the frame now coming
  counted_ = true;
  const double gain = judge(tallies, moving, box_pixels, true);
  if (frame_rays == 0) return;
  if (saves_too_little(gain, frame_rays))
    go_plain();
  else
    plain_strikes_ = 0;
}

bool object_gate::probe(const std::vector<gate_entry>& tallies, std::uint64_t rays, std::uint64_t bounded,
                        std::uint64_t cast) {
  if (!enabled()) return false;
  // A view's probe pixels build their cells alone, so what builds cost is not judged
  // here: the frame after, with every pixel counted, does that.
  const double gain = judge(tallies, false, nullptr, false);
  if (!saves_too_little(gain, rays)) return false;
  go_plain();
  allowance_wait_ = bounds_too_few(bounded, cast) ? 8 : 0;
  return true;
}

void object_gate::plain_done(std::uint64_t bounded, std::uint64_t cast) {
  plain_left_ -= plain_left_ > 0;
  counted_ = false;
  ++frame_;  // objects' waits run on
  if (allowance_wait_ > 0) {
    --allowance_wait_;
  } else if (bounds_too_few(bounded, cast)) {
    allowance_wait_ = 8;
  }
}

std::size_t object_gate::objects_off() const {
  return std::size_t(std::count_if(off_until_.begin(), off_until_.end(), [&](std::uint32_t u) { return frame_ < u; }));
}

}  // namespace epsray
