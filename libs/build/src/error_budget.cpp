#include "terralod/build/error_budget.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace terralod {

Result<ErrorBudget> makeErrorBudget(const TreeLayout& layout, double leafError,
                                    double heightRange) {
  if (!(leafError > 0) || !std::isfinite(leafError))
    return Error{"--max-error must be a positive number of metres"};
  ErrorBudget b;
  b.levelError = levelErrors(layout, leafError);
  const int32_t levels = layout.levelCount();
  b.zStep.resize(levels);
  b.buildThreshold.resize(levels);
  b.chunkRangeBound.resize(levels);
  for (int32_t l = 0; l < levels; ++l) {
    const double e = b.levelError[l];
    // Surface heights span at most the relief; a skirt hangs at most (own morph error, <= 2e)
    // + (coarsest neighbour's error, <= levelError[0]) below it; 2e more is slack.
    b.chunkRangeBound[l] = heightRange + b.levelError[0] + 4.0 * e;
    b.zStep[l] = std::max(b.chunkRangeBound[l] / 65535.0, e / 64.0);
    b.buildThreshold[l] = e - 0.5 * b.zStep[l];
  }
  if (b.buildThreshold[levels - 1] < 0.75 * leafError) {
    // zStep <= leafError/2 holds when leafError * (65535/2 - 2^depth - 4) >= heightRange.
    const double smallest = heightRange / (32767.5 - std::ldexp(1.0, layout.depth) - 4.0);
    char text[256];
    std::snprintf(text, sizeof text,
                  "--max-error %g m is too fine for 16-bit heights over %.0f m of relief; "
                  "use at least %.3g m",
                  leafError, heightRange, smallest * 1.001);
    return Error{text};
  }
  return b;
}

}  // namespace terralod
