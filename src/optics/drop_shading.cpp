#include "optics/drop_shading.h"

#include <algorithm>
#include <stdexcept>

namespace pluvia::optics {

DropMethod parseDropMethod(const std::string& word) {
  if (word == "default") return DropMethod::Default;
  if (word == "paper") return DropMethod::Paper;
  if (word == "trace") return DropMethod::Trace;
  throw std::invalid_argument("unknown drop shading method '" + word + "' (default, paper, trace)");
}

std::array<DropOptics, 3> channelOptics(const std::array<double, 3>& eta, int terms) {
  return {DropOptics{eta[0], terms}, DropOptics{eta[1], terms}, DropOptics{eta[2], terms}};
}

PaperShading preparePaperShading(const EquirectMap& environment, const std::array<double, 3>& eta,
                                 int order, int terms, ShWindow window) {
  PaperShading paper;
  paper.environmentSh = projectEnvironment(environment, order, window);
  for (size_t c = 0; c < 3; ++c) {
    paper.zonal[c] = (c > 0 && eta[c] == eta[0]) ? paper.zonal[0]
                                                 : transferZonal(DropOptics{eta[c], terms}, order);
  }
  return paper;
}

std::array<double, 3> shadePaper(const PaperShading& paper, const EquirectMap& environment,
                                 const std::array<double, 3>& view) {
  std::array<double, 3> radiance = shadeZonal(paper.environmentSh, paper.zonal, view);
  const std::array<float, 3> background =
      sampleEquirect(environment, float(view[0]), float(view[1]), float(view[2]));
  for (size_t c = 0; c < 3; ++c) {
    radiance[c] = std::max(radiance[c], 0.0) + paper.backgroundWeight * background[c];
  }
  return radiance;
}

}  // namespace pluvia::optics
