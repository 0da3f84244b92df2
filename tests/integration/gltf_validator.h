#pragma once
// The Khronos glTF validator (npm, pinned in tests/tools) run on one asset, for the export tests.
// Needs TERRALOD_NODE and TERRALOD_SOURCE_DIR (the integration tests define them).

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.h"

namespace terralod::test {

// Runs the Khronos glTF validator: no errors, no warnings.
inline void expectValidGltf(const std::string& glb) {
  const std::string node = TERRALOD_NODE;
  const std::string tools = std::string(TERRALOD_SOURCE_DIR) + "/tests/tools";
  ASSERT_FALSE(node.empty()) << "node was not found when configuring; it runs the glTF validator";
  ASSERT_TRUE(std::filesystem::exists(tools + "/node_modules/gltf-validator/package.json"))
      << "the Khronos glTF validator is not installed: run scripts/install-deps.sh (make test "
         "does), which runs `npm ci` in tests/tools";
  const RunResult validated = runProgram(node, {tools + "/validate-gltf.mjs", glb});
  const auto report = nlohmann::json::parse(validated.out, nullptr, false);
  ASSERT_FALSE(report.is_discarded()) << validated.out << validated.err;
  EXPECT_EQ(report["errors"].get<int>(), 0) << report.dump(2);
  EXPECT_EQ(report["warnings"].get<int>(), 0) << report.dump(2);
  EXPECT_EQ(validated.exitCode, 0) << validated.err;
  std::printf("glTF validator %s on %s: %d errors, %d warnings, %d infos, %d hints\n",
              report["validator"].get<std::string>().c_str(), glb.c_str(),
              report["errors"].get<int>(), report["warnings"].get<int>(),
              report["infos"].get<int>(), report["hints"].get<int>());
}

}  // namespace terralod::test
