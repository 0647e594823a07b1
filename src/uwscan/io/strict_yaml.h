// A YAML mapping whose keys are checked: every key must be known and read,
// and every error names the file and the key (rig.yaml, scene.yaml).
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <array>
#include <set>
#include <string>
#include <vector>

#include "uwscan/geometry/rigid3d.h"
#include "uwscan/util/error.h"

namespace uwscan {

class StrictMap {
 public:
  StrictMap(const YAML::Node& node, std::string where, std::string source);

  std::string Name(const std::string& key) const;
  YAML::Node Get(const std::string& key);
  bool Has(const std::string& key) const { return node_[key].IsDefined(); }
  StrictMap Child(const std::string& key) { return StrictMap(Get(key), Name(key), source_); }

  double Number(const std::string& key);
  int Integer(const std::string& key);
  uint64_t Unsigned(const std::string& key);
  bool Bool(const std::string& key);
  std::string String(const std::string& key);
  Eigen::Vector3d Vector3(const std::string& key);
  std::vector<double> Numbers(const std::string& key);  // a list of any length
  template <size_t N>
  std::array<double, N> Vector(const std::string& key) {
    const YAML::Node value = Get(key);
    UWS_CHECK(value.IsSequence() && value.size() == N, source_, ": '", Name(key),
              "' must be a list of ", N, " numbers");
    std::array<double, N> result;
    for (size_t i = 0; i < N; ++i)
      result[i] = ToNumber(value[i], Name(key) + "[" + std::to_string(i) + "]");
    return result;
  }
  Rigid3d Pose(const std::string& key);  // {q: [w, x, y, z], t: [x, y, z]}

  // Throws on the first key that was never asked for.
  void CheckNoUnknownKeys() const;
  const std::string& source() const { return source_; }

 private:
  double ToNumber(const YAML::Node& value, const std::string& name) const;

  YAML::Node node_;
  std::string where_, source_;
  std::set<std::string> seen_;
};

// Shortest text that reads back to the same double.
std::string YamlNumber(double value);
std::string YamlVector(const Eigen::Vector3d& v);
std::string YamlPose(const Rigid3d& pose);

}  // namespace uwscan
