#include "uwscan/io/strict_yaml.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

#include "uwscan/util/error.h"

namespace uwscan {

StrictMap::StrictMap(const YAML::Node& node, std::string where, std::string source)
    : node_(node), where_(std::move(where)), source_(std::move(source)) {
  UWS_CHECK(node_.IsMap(), source_, ": '", where_.empty() ? "(top level)" : where_,
            "' must be a mapping");
}

std::string StrictMap::Name(const std::string& key) const {
  if (where_.empty()) return key;
  return key.empty() ? where_ : where_ + "." + key;
}

YAML::Node StrictMap::Get(const std::string& key) {
  seen_.insert(key);
  const YAML::Node value = node_[key];
  UWS_CHECK(value.IsDefined() && !value.IsNull(), source_, ": missing key '", Name(key), "'");
  return value;
}

double StrictMap::ToNumber(const YAML::Node& value, const std::string& name) const {
  UWS_CHECK(value.IsScalar(), source_, ": '", name, "' must be a number");
  const std::string& text = value.Scalar();
  double number = 0.0;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), number);
  UWS_CHECK(result.ec == std::errc() && result.ptr == text.data() + text.size(), source_, ": '",
            name, "' must be a number (got '", text, "')");
  UWS_CHECK(std::isfinite(number), source_, ": '", name, "' must be finite (got '", text, "')");
  return number;
}

double StrictMap::Number(const std::string& key) { return ToNumber(Get(key), Name(key)); }

int StrictMap::Integer(const std::string& key) {
  const double value = Number(key);
  UWS_CHECK(value == std::floor(value) && std::abs(value) < 1e9, source_, ": '", Name(key),
            "' must be an integer");
  return static_cast<int>(value);
}

uint64_t StrictMap::Unsigned(const std::string& key) {
  const YAML::Node value = Get(key);
  UWS_CHECK(value.IsScalar(), source_, ": '", Name(key), "' must be an unsigned integer");
  const std::string& text = value.Scalar();
  uint64_t number = 0;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), number);
  UWS_CHECK(result.ec == std::errc() && result.ptr == text.data() + text.size(), source_, ": '",
            Name(key), "' must be an unsigned integer (got '", text, "')");
  return number;
}

bool StrictMap::Bool(const std::string& key) {
  const std::string text = String(key);
  UWS_CHECK(text == "true" || text == "false", source_, ": '", Name(key),
            "' must be true or false (got '", text, "')");
  return text == "true";
}

std::string StrictMap::String(const std::string& key) {
  const YAML::Node value = Get(key);
  UWS_CHECK(value.IsScalar(), source_, ": '", Name(key), "' must be a scalar");
  return value.Scalar();
}

std::vector<double> StrictMap::Numbers(const std::string& key) {
  const YAML::Node value = Get(key);
  UWS_CHECK(value.IsSequence(), source_, ": '", Name(key), "' must be a list of numbers");
  std::vector<double> result;
  for (size_t i = 0; i < value.size(); ++i)
    result.push_back(ToNumber(value[i], Name(key) + "[" + std::to_string(i) + "]"));
  return result;
}

Eigen::Vector3d StrictMap::Vector3(const std::string& key) {
  const std::array<double, 3> v = Vector<3>(key);
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

Rigid3d StrictMap::Pose(const std::string& key) {
  StrictMap pose = Child(key);
  const YAML::Node q = pose.Get("q");
  UWS_CHECK(q.IsSequence() && q.size() == 4, source_, ": '", pose.Name("q"),
            "' must be a list of 4 numbers (w x y z)");
  double w[4];
  for (int i = 0; i < 4; ++i) w[i] = ToNumber(q[i], pose.Name("q") + "[" + std::to_string(i) + "]");
  const Eigen::Quaterniond rotation(w[0], w[1], w[2], w[3]);
  UWS_CHECK(std::abs(rotation.norm() - 1.0) < 1e-6, source_, ": '", pose.Name("q"),
            "' must be a unit quaternion");
  const Eigen::Vector3d t = pose.Vector3("t");
  pose.CheckNoUnknownKeys();
  return Rigid3d(rotation, t);
}

void StrictMap::CheckNoUnknownKeys() const {
  for (const auto& entry : node_) {
    const std::string key = entry.first.as<std::string>();
    UWS_CHECK(seen_.count(key), source_, ": unknown key '", Name(key), "'");
  }
}

std::string YamlNumber(double value) { return fmt::format("{}", value); }

std::string YamlVector(const Eigen::Vector3d& v) {
  return fmt::format("[{}, {}, {}]", v.x(), v.y(), v.z());
}

std::string YamlPose(const Rigid3d& pose) {
  const Eigen::Quaterniond& q = pose.rotation;
  return fmt::format("{{q: [{}, {}, {}, {}], t: {}}}", q.w(), q.x(), q.y(), q.z(),
                     YamlVector(pose.translation));
}

}  // namespace uwscan
