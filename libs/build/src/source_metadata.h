#pragma once
// The metadata's "source" object (docs/format.md "Metadata"): how the DEM was read, for info
// and verify; and the warnings about how it was read. Shared by both chunk kinds' builders.

#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "terralod/raster/dem_reader.h"

namespace terralod {

nlohmann::json sourceMetadata(const DemInfo& info);

/// Warns when the raster looks like a picture or its spacing was assumed. Call once the
/// input has proven usable, so a broken input gets its one error line.
void warnAboutSource(const DemInfo& info, const std::function<void(const std::string&)>& warn);

}  // namespace terralod
