#include <camdyn/scene.h>

#include <filesystem>
#include <memory>
#include <utility>

#include "api/scene_impl.h"
#include "common/errors.h"
#include "io/config.h"
#include "io/json_archive.h"
#include "io/json_writer.h"

namespace camdyn {

Scene::Impl::Impl(const Json& document, const ConfigSource& source)
    : scene(scene_from_json(document, source)), file(source.file), model(build_model(scene, file)) {}

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

}  // namespace camdyn
