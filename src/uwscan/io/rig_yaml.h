// rig.yaml (format uwscan-rig/1, architecture.md): strict reader and exact
// writer. Unknown or missing keys and invalid values are errors naming the
// file and the key.
#pragma once

#include <filesystem>
#include <string>

#include "uwscan/sensor/rig.h"

namespace uwscan {

Rig ReadRigYaml(const std::filesystem::path& path);
// Parses YAML text; `source` names it in errors.
Rig ParseRigYaml(const std::string& text, const std::string& source);

std::string RigToYaml(const Rig& rig);
// Validates, then writes atomically.
void WriteRigYaml(const std::filesystem::path& path, const Rig& rig);

}  // namespace uwscan
