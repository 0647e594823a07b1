// uwscan camera project|backproject
#include <optional>

#include "commands.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/csv.h"
#include "uwscan/util/error.h"

namespace uwscan::cli {
namespace {

struct ProjectArgs {
  std::string rig, camera, method = "exact", in, out;
  int iterations = 2;
};

struct BackprojectArgs {
  std::string rig, camera, in, out;
};

void RunProject(const ProjectArgs& args) {
  const auto method = ProjectionMethodFromName(args.method);
  if (!method) throw UsageError("--method must be exact, taylor or pinhole");
  if (args.iterations < 1 || args.iterations > 50) throw UsageError("--iterations must be 1..50");
  RefuseOutputOntoInput("--out", args.out, {args.in, args.rig});
  const Rig rig = ReadRigYaml(args.rig);
  const Camera& camera = rig.CameraByName(args.camera);
  const CsvTable points = ReadNumericCsv(args.in, {"x", "y", "z"});
  CsvTable pixels;
  pixels.header = {"u", "v", "valid"};
  for (const auto& row : points.rows) {
    const auto pixel =
        camera.Project(Eigen::Vector3d(row[0], row[1], row[2]), *method, args.iterations);
    pixels.rows.push_back(pixel ? std::vector<double>{pixel->x(), pixel->y(), 1.0}
                                : std::vector<double>{0.0, 0.0, 0.0});
  }
  WriteNumericCsv(args.out, pixels);
}

void RunBackproject(const BackprojectArgs& args) {
  RefuseOutputOntoInput("--out", args.out, {args.in, args.rig});
  const Rig rig = ReadRigYaml(args.rig);
  const Camera& camera = rig.CameraByName(args.camera);
  const CsvTable pixels = ReadNumericCsv(args.in, {"u", "v"});
  CsvTable rays;
  rays.header = {"ox", "oy", "oz", "dx", "dy", "dz", "valid"};
  for (const auto& row : pixels.rows) {
    const auto ray = camera.BackProject(Eigen::Vector2d(row[0], row[1]));
    if (ray) {
      rays.rows.push_back({ray->origin.x(), ray->origin.y(), ray->origin.z(), ray->direction.x(),
                           ray->direction.y(), ray->direction.z(), 1.0});
    } else {
      rays.rows.push_back({0, 0, 0, 0, 0, 0, 0});
    }
  }
  WriteNumericCsv(args.out, rays);
}

}  // namespace

void RegisterCameraCommands(CLI::App& app) {
  auto* camera =
      app.add_subcommand("camera", "Project points and back-project pixels with a rig's camera");
  camera->require_subcommand(1);

  auto project_args = std::make_shared<ProjectArgs>();
  auto* project = camera->add_subcommand(
      "project", "Camera-frame points (x,y,z) -> pixels (u,v,valid); invalid rows have valid=0");
  project->add_option("--rig", project_args->rig, "rig.yaml")->required();
  project->add_option("--camera", project_args->camera, "camera name (default: the first)");
  project->add_option("--method", project_args->method, "exact | taylor | pinhole")
      ->capture_default_str();
  project->add_option("--iterations", project_args->iterations, "Taylor iterations")
      ->capture_default_str();
  project->add_option("--in", project_args->in, "points.csv with columns x,y,z")->required();
  project->add_option("--out", project_args->out, "pixels.csv")->required();
  project->callback([project_args] { RunProject(*project_args); });

  auto back_args = std::make_shared<BackprojectArgs>();
  auto* back = camera->add_subcommand("backproject",
                                      "Pixels (u,v) -> rays in water (ox,oy,oz,dx,dy,dz,valid)");
  back->add_option("--rig", back_args->rig, "rig.yaml")->required();
  back->add_option("--camera", back_args->camera, "camera name (default: the first)");
  back->add_option("--in", back_args->in, "pixels.csv with columns u,v")->required();
  back->add_option("--out", back_args->out, "rays.csv")->required();
  back->callback([back_args] { RunBackproject(*back_args); });
}

}  // namespace uwscan::cli
