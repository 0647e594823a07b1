#include "uwscan/io/rig_yaml.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "uwscan/io/strict_yaml.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

constexpr const char* kFormat = "uwscan-rig/1";

Rigid3d ReadPose(StrictMap& parent, const std::string& key) {
  StrictMap pose = parent.Child(key);
  const auto q = pose.Vector<4>("q");
  const auto t = pose.Vector<3>("t");
  pose.CheckNoUnknownKeys();
  const Eigen::Quaterniond rotation(q[0], q[1], q[2], q[3]);
  const double norm = rotation.norm();
  UWS_CHECK(std::abs(norm - 1.0) < 1e-3, parent.source(), ": '", pose.Name("q"),
            "' must be a unit quaternion w x y z (norm ", norm, ")");
  return Rigid3d(rotation, Eigen::Vector3d(t[0], t[1], t[2]));
}

Camera ReadCamera(const YAML::Node& node, const std::string& where, const std::string& source) {
  StrictMap map(node, where, source);
  Camera camera;
  camera.name = map.String("name");
  camera.width = map.Integer("width");
  camera.height = map.Integer("height");
  camera.bayer = map.String("bayer");
  const std::string model = map.String("model");
  const auto model_id = CameraModelFromName(model);
  UWS_CHECK(model_id.has_value(), source, ": '", map.Name("model"),
            "' must be pinhole or flatport (got '", model, "')");
  camera.model = *model_id;
  camera.intrinsics = {map.Number("fx"), map.Number("fy"), map.Number("cx"), map.Number("cy")};
  // OpenCV's order, as OpenCV and ROS write it: k1 k2 p1 p2 [k3 [k4 k5 k6
  // [s1 s2 s3 s4 [tx ty]]]]; uwscan's lens has the first five.
  const std::vector<double> distortion = map.Numbers("distortion");
  const size_t n = distortion.size();
  UWS_CHECK(n == 4 || n == 5 || n == 8 || n == 12 || n == 14, source, ": '", map.Name("distortion"),
            "' must be OpenCV's k1, k2, p1, p2[, k3] (got ", n, " numbers)");
  for (size_t i = 5; i < n; ++i) {
    UWS_CHECK(distortion[i] == 0.0, source, ": '", map.Name("distortion"), "' has ", n,
              " coefficients and the ", i + 1,
              "th is not 0: OpenCV's rational or thin-prism model, which uwscan's lens (k1, k2, "
              "p1, p2, k3) does not hold; calibrate with `uwscan calibrate camera`");
  }
  camera.distortion = {distortion[0], distortion[1], distortion[2], distortion[3],
                       n > 4 ? distortion[4] : 0.0};
  if (camera.IsFlatPort()) {
    StrictMap port = map.Child("port");
    const auto normal = port.Vector<3>("normal");
    camera.port.normal = Eigen::Vector3d(normal[0], normal[1], normal[2]);
    camera.port.d_air = port.Number("d_air");
    camera.port.d_glass = port.Number("d_glass");
    camera.port.n_air = port.Number("n_air");
    camera.port.n_glass = port.Number("n_glass");
    camera.port.n_water = port.Number("n_water");
    port.CheckNoUnknownKeys();
  } else {
    UWS_CHECK(!map.Has("port"), source, ": '", map.Name("port"),
              "' is only allowed with model: flatport");
  }
  camera.rig_from_camera = ReadPose(map, "rig_from_camera");
  map.CheckNoUnknownKeys();
  camera.Check(source + ": " + where);
  return camera;
}

LineProjector ReadLaser(const YAML::Node& node, const std::string& where,
                        const std::string& source) {
  StrictMap map(node, where, source);
  LineProjector laser;
  laser.name = map.String("name");
  laser.camera_from_laser = ReadPose(map, "camera_from_laser");
  laser.p1 = map.Number("p1");
  laser.wavelength_nm = map.Number("wavelength_nm");
  map.CheckNoUnknownKeys();
  laser.Check(source + ": " + where);
  return laser;
}

template <typename Container>
std::string List(const Container& values) {
  std::string out = "[";
  bool first = true;
  for (double v : values) {
    out += (first ? "" : ", ") + YamlNumber(v);
    first = false;
  }
  return out + "]";
}

std::string Pose(const Rigid3d& pose) {
  const auto& q = pose.rotation;
  return "{q: " + List(std::array<double, 4>{q.w(), q.x(), q.y(), q.z()}) +
         ", t: " + List(pose.translation) + "}";
}

}  // namespace

Rig ParseRigYaml(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    UWS_THROW(source, ": not valid YAML: ", e.what());
  }
  UWS_CHECK(root.IsDefined() && !root.IsNull(), source, ": empty rig file");
  StrictMap map(root, "", source);
  // An OpenCV calibration (cv::FileStorage, calibrate.py, ROS camera_info)
  // is the file a user most likely has: say what it is and what to do.
  UWS_CHECK(
      map.Has("format") || !(map.Has("camera_matrix") || map.Has("K")), source,
      ": an OpenCV or ROS calibration (camera_matrix), not a uwscan rig; a rig (format: ", kFormat,
      ") also has the flat port and the laser: make one with `uwscan calibrate`, "
      "or write it by hand with this file's fx, fy, cx, cy and distortion "
      "(architecture.md, rig.yaml)");
  const std::string format = map.String("format");
  UWS_CHECK(format == kFormat, source, ": 'format' must be ", kFormat, " (got '", format, "')");
  Rig rig;
  const YAML::Node cameras = map.Get("cameras");
  UWS_CHECK(cameras.IsSequence() && cameras.size() > 0, source,
            ": 'cameras' must be a non-empty list");
  for (size_t i = 0; i < cameras.size(); ++i) {
    rig.cameras.push_back(ReadCamera(cameras[i], "cameras[" + std::to_string(i) + "]", source));
  }
  if (map.Has("lasers")) {
    const YAML::Node lasers = map.Get("lasers");
    UWS_CHECK(lasers.IsSequence(), source, ": 'lasers' must be a list");
    for (size_t i = 0; i < lasers.size(); ++i) {
      rig.lasers.push_back(ReadLaser(lasers[i], "lasers[" + std::to_string(i) + "]", source));
    }
  }
  map.CheckNoUnknownKeys();
  rig.Check(source);
  return rig;
}

Rig ReadRigYaml(const std::filesystem::path& path) {
  std::ifstream in(path);
  UWS_CHECK(in.good(), path.string(), ": cannot open rig file");
  std::stringstream text;
  text << in.rdbuf();
  Rig rig = ParseRigYaml(text.str(), path.string());
  rig.source = path.string();
  return rig;
}

std::string RigToYaml(const Rig& rig) {
  std::ostringstream out;
  out << "format: " << kFormat << "\ncameras:\n";
  for (const auto& c : rig.cameras) {
    out << "  - name: " << c.name << "\n"
        << "    width: " << c.width << "\n"
        << "    height: " << c.height << "\n"
        << "    bayer: " << c.bayer << "\n"
        << "    model: " << CameraModelName(c.model) << "\n"
        << "    fx: " << YamlNumber(c.intrinsics[0]) << "\n"
        << "    fy: " << YamlNumber(c.intrinsics[1]) << "\n"
        << "    cx: " << YamlNumber(c.intrinsics[2]) << "\n"
        << "    cy: " << YamlNumber(c.intrinsics[3]) << "\n"
        << "    distortion: " << List(c.distortion) << "\n";
    if (c.IsFlatPort()) {
      out << "    port:\n"
          << "      normal: " << List(c.port.normal) << "\n"
          << "      d_air: " << YamlNumber(c.port.d_air) << "\n"
          << "      d_glass: " << YamlNumber(c.port.d_glass) << "\n"
          << "      n_air: " << YamlNumber(c.port.n_air) << "\n"
          << "      n_glass: " << YamlNumber(c.port.n_glass) << "\n"
          << "      n_water: " << YamlNumber(c.port.n_water) << "\n";
    }
    out << "    rig_from_camera: " << Pose(c.rig_from_camera) << "\n";
  }
  if (!rig.lasers.empty()) {
    out << "lasers:\n";
    for (const auto& l : rig.lasers) {
      out << "  - name: " << l.name << "\n"
          << "    camera_from_laser: " << Pose(l.camera_from_laser) << "\n"
          << "    p1: " << YamlNumber(l.p1) << "\n"
          << "    wavelength_nm: " << YamlNumber(l.wavelength_nm) << "\n";
    }
  }
  return out.str();
}

void WriteRigYaml(const std::filesystem::path& path, const Rig& rig) {
  rig.Check(path.string());
  WriteFileAtomic(path, RigToYaml(rig));
}

}  // namespace uwscan
