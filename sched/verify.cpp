#include "verify.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace epsray {

double pixel_error(glm::vec3 la, glm::vec3 lw) {
  double e = 0;
  for (int c = 0; c < 3; ++c) {
    double den = std::max(double(lw[c]), 1.0 / 255);
    e = std::max(e, std::fabs(double(la[c]) - double(lw[c])) / den);
  }
  return std::isnan(e) ? INFINITY : e;
}

verify_result verify_frame(workers& pool, const world& w, const camera& cam, const image& acc, float eps) {
  frame_params bp;
  bp.mode = render_mode::base;
  frame_result ref = render_frame(pool, w, cam, bp);
  std::vector<double> errs(acc.pixels.size());
  verify_result r;
  for (size_t i = 0; i < errs.size(); ++i) {
    errs[i] = pixel_error(acc.pixels[i], ref.img.pixels[i]);
    r.max_rel_err = std::max(r.max_rel_err, errs[i]);
    if (errs[i] > double(eps)) ++r.violations;
    r.mean_rel_err += errs[i];
  }
  if (!errs.empty()) {
    r.mean_rel_err /= double(errs.size());
    size_t k = std::min(errs.size() - 1, size_t(0.999 * double(errs.size())));
    std::nth_element(errs.begin(), errs.begin() + std::ptrdiff_t(k), errs.end());
    r.p999_rel_err = errs[k];
  }
  return r;
}

}  // namespace epsray
