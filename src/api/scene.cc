#include <camdyn/scene.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <utility>

#include "api/argument_checks.h"
#include "api/scene_impl.h"
#include "common/errors.h"
#include "dynamics/cam_outline.h"
#include "dynamics/rigid_jump_speed.h"
#include "io/config.h"
#include "io/dotted_path.h"
#include "io/json_archive.h"
#include "io/json_writer.h"
#include "study/simulation_output.h"

namespace camdyn {

Scene::Impl::Impl(const Json& document, const ConfigSource& from)
    : scene(scene_from_json(document, from)), source(from), file(from.file), model(build_model(scene, file)) {}

namespace {

/// The model of `scene` on the geometry of `before` (`previous`'s model) where the two scenes share it.
Model model_after_change(const SceneConfig& scene, const SceneConfig& before, const Model& previous,
                         const std::string& file) {
  if (CamGeometryKey(scene) == CamGeometryKey(before))
    return build_model(static_cast<const CamGeometry&>(previous), scene, file);
  return build_model(scene, file);
}

}  // namespace

Scene::Impl::Impl(const Json& document, const Impl& previous)
    : scene(scene_from_json(document, previous.source)),
      source(previous.source),
      file(previous.file),
      model(model_after_change(scene, previous.scene, previous.model, file)) {}

void Scene::set(const std::string& path, double value) {
  // JSON has no NaN or inf (they would arrive as null): named as such here.
  if (!std::isfinite(value))
    throw InputError("", path,
                     "expected a finite number, got " + std::string(std::isnan(value) ? "nan"
                                                                    : value > 0       ? "inf"
                                                                                      : "-inf"));
  naming_file(impl_->file, [&] {
    Json document = to_json(impl_->scene);
    set_dotted_field(document, path, Json(value));
    impl_ = std::make_shared<const Impl>(document, *impl_);
  });
}

void Scene::set(const std::string& path, const std::string& value) {
  naming_file(impl_->file, [&] {
    Json document = to_json(impl_->scene);
    apply_assignment(document, path + "=" + value);
    impl_ = std::make_shared<const Impl>(document, *impl_);
  });
}

Scene::Scene(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}

Scene Scene::load(const std::string& file, const std::vector<std::string>& overrides) {
  return naming_file(file, [&] {
    return Scene(std::make_shared<const Impl>(load_config_json(file, overrides), config_source(file)));
  });
}

Scene Scene::from_json(const std::string& json_text, const std::string& base_dir,
                       const std::vector<std::string>& overrides) {
  Json document = parse_json_text(json_text, "");
  for (const std::string& assignment : overrides) apply_assignment(document, assignment);
  const std::string dir = std::filesystem::absolute(base_dir.empty() ? "." : base_dir).lexically_normal().string();
  return Scene(std::make_shared<const Impl>(document, ConfigSource{"", dir}));
}

const std::string& Scene::name() const { return impl_->scene.name; }

double Scene::rpm() const { return impl_->scene.mechanism.cam.rpm; }

std::string Scene::resolved_json() const { return dump_json(to_json(impl_->scene)); }

double Scene::jump_speed_rpm() const { return camdyn::jump_speed_rpm(impl_->model); }

ModelInfo Scene::model() const {
  const Model& m = impl_->model;
  return {m.layout.names, m.elements, drive_name(m), follower_name(m), contact_pair_name(m)};
}

CamProfile Scene::profile(int points) const {
  if (points < 3) throw InputError("", "points", "must be at least 3, got " + std::to_string(points));
  check_point_count("points", static_cast<std::size_t>(points));
  CamOutline o = cam_outline(impl_->model, points);
  return {std::move(o.u), std::move(o.contour_x), std::move(o.contour_y), std::move(o.pitch_x), std::move(o.pitch_y)};
}

LawValues Scene::law(const std::vector<double>& angles_deg) const {
  check_point_count("angles_deg", angles_deg.size());
  check_finite("angles_deg", angles_deg, "[deg]");
  LawValues v;
  for (std::vector<double>* column : {&v.s, &v.ds, &v.d2s, &v.d3s}) column->reserve(angles_deg.size());
  for (const double angle : angles_deg) {
    const LawSample l = impl_->model.law->eval(angle * std::numbers::pi / 180.0);
    v.s.push_back(l.s);
    v.ds.push_back(l.ds);
    v.d2s.push_back(l.d2s);
    v.d3s.push_back(l.d3s);
  }
  return v;
}

}  // namespace camdyn
