#include "behaviour/registry.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <sstream>

#include "behaviour/descriptor_check.hpp"
#include "behaviour/params.hpp"
#include "behaviour/plugin.hpp"
#include "common/input_error.hpp"

namespace swarmform::behaviour {
namespace {

namespace fs = std::filesystem;

// `path` lies under `folder` (both canonical): folder's components are a prefix of path's.
bool under(const fs::path& path, const fs::path& folder) {
  auto p = path.begin();
  for (auto f = folder.begin(); f != folder.end(); ++f, ++p) {
    if (f->empty()) continue;  // a trailing separator
    if (p == path.end() || *p != *f) return false;
  }
  return true;
}

}  // namespace

Registry::Registry(std::vector<fs::path> folders) {
  for (const fs::path& f : folders) add_folder(f);
}

void Registry::add(const Descriptor& d) {
  if (d.name.empty() || d.make == nullptr)
    throw std::logic_error("behaviour descriptor without name or make");
  if (const std::string why = check_descriptor(d); !why.empty()) throw std::logic_error(why);
  if (!by_name_.emplace(std::string(d.name), &d).second) {
    throw std::logic_error("behaviour '" + std::string(d.name) + "' registered twice");
  }
}

void Registry::add_folder(const fs::path& folder) {
  std::error_code ec;
  fs::path canonical = fs::canonical(folder, ec);
  if (ec) return;  // a folder that does not exist holds no plug-in: nothing can be loaded from it
  for (const fs::path& f : folders_) {
    if (f == canonical) return;
  }
  folders_.push_back(std::move(canonical));
}

void Registry::add_folders_from_environment() {
  const char* value = std::getenv(kPluginPathVariable);
  if (value == nullptr) return;
  std::stringstream list(value);
  std::string folder;
  while (std::getline(list, folder, ':')) {
    if (!folder.empty()) add_folder(folder);
  }
}

const Descriptor* Registry::find(std::string_view name) const {
  auto it = by_name_.find(name);
  return it == by_name_.end() ? nullptr : it->second;
}

std::string Registry::names() const {
  std::string s;
  for (const auto& [name, d] : by_name_) s += (s.empty() ? "" : ", ") + name;
  return s.empty() ? "none" : s;
}

std::string Registry::folders_text() const {
  std::string s;
  for (const fs::path& f : folders_) s += (s.empty() ? "" : ", ") + f.string();
  return s.empty() ? "none" : s;
}

const Descriptor& Registry::load_plugin(const std::string& path) {
  const std::string what = "plug-in '" + path + "'";
  std::error_code ec;
  const fs::path canonical = fs::canonical(path, ec);
  if (ec) throw PluginError(what + ": " + ec.message());
  if (auto it = by_path_.find(canonical.string()); it != by_path_.end()) return *it->second;
  bool allowed = false;
  for (const fs::path& f : folders_) allowed = allowed || under(canonical, f);
  if (!allowed) {
    throw PluginError(what + " (" + canonical.string() + ") lies outside the allowed plug-in folders (" +
                      folders_text() + "): refused; give its folder with --plugin-dir or in " +
                      kPluginPathVariable);
  }
  if (!fs::is_regular_file(canonical, ec)) throw PluginError(what + ": not a regular file");
  // RTLD_LOCAL: two plug-ins' own symbols never interpose. Never dlclosed (registry.hpp).
  void* handle = dlopen(canonical.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* err = dlerror();
    throw PluginError(what + ": cannot load: " + (err ? err : "unknown dlopen error"));
  }
  using Entry = const Descriptor* (*)();
  auto entry = reinterpret_cast<Entry>(dlsym(handle, SWARMFORM_BEHAVIOUR_ENTRY));
  if (entry == nullptr) {
    throw PluginError(what + ": exports no " SWARMFORM_BEHAVIOUR_ENTRY
                             "() (add SWARMFORM_BEHAVIOUR(descriptor) from behaviour/plugin.hpp)");
  }
  const Descriptor* d = entry();
  if (d == nullptr) throw PluginError(what + ": " SWARMFORM_BEHAVIOUR_ENTRY "() returned no descriptor");
  if (d->api_version != kApiVersion) {
    throw PluginError(what + ": built against behaviour API version " + std::to_string(d->api_version) +
                      ", this program has version " + std::to_string(kApiVersion) + "; rebuild the plug-in");
  }
  if (d->name.empty() || d->make == nullptr)
    throw PluginError(what + ": its descriptor has no name or no make");
  if (const std::string why = check_descriptor(*d); !why.empty()) throw PluginError(what + ": " + why);
  if (const Descriptor* other = find(d->name); other != nullptr && other != d) {
    throw PluginError(what + ": names behaviour '" + std::string(d->name) +
                      "', which is already registered (a built-in or another plug-in)");
  }
  by_name_.emplace(std::string(d->name), d);
  by_path_.emplace(canonical.string(), d);
  return *d;
}

const Descriptor& Registry::load_descriptor(const std::string& path) {
  std::error_code ec;
  const fs::path canonical = fs::canonical(path, ec);
  if (ec) throw InputError(path, 0, "cannot read the behaviour's descriptor file: " + ec.message());
  if (auto it = described_.find(canonical.string()); it != described_.end()) return it->second->descriptor();
  std::unique_ptr<const DescribedBehaviour> b = load_descriptor_file(path);
  const Descriptor& d = b->descriptor();
  if (find(d.name) != nullptr) {
    throw InputError(path, 0,
                     "name: behaviour '" + std::string(d.name) +
                         "' is already registered (a built-in, a plug-in or another descriptor file)");
  }
  by_name_.emplace(std::string(d.name), &d);
  described_.emplace(canonical.string(), std::move(b));
  return d;
}

std::string no_controller_message(std::string_view behaviour, const std::string& file) {
  const std::string by = file.empty() ? std::string("a descriptor file") : fs::path(file).filename().string();
  return "behaviour '" + std::string(behaviour) + "' is described by " + by +
         " and has no controller: its agents run it with robot_agent --exec / swarm run --exec";
}

const Descriptor& Registry::resolve(const Mission& mission) {
  if (!mission.descriptor.empty()) {
    auto it = described_.find(mission.descriptor);
    if (it == described_.end() || it->second->descriptor().name != mission.behaviour)
      throw InputError("<mission>", 0, no_controller_message(mission.behaviour, mission.descriptor));
    return it->second->descriptor();
  }
  if (!mission.plugin.empty()) {
    const Descriptor& d = load_plugin(mission.plugin);
    if (d.name != mission.behaviour) {
      throw InputError("<mission>", 0,
                       "plug-in '" + mission.plugin + "' holds behaviour '" + std::string(d.name) +
                           "', the mission names '" + mission.behaviour + "'");
    }
    return d;
  }
  const Descriptor* d = find(mission.behaviour);
  if (d == nullptr) {
    throw InputError("<mission>", 0,
                     "unknown behaviour '" + mission.behaviour + "' (built in: " + names() +
                         "; a plug-in is named by its library: behaviour: {plugin: path/libx.so})");
  }
  return *d;
}

std::unique_ptr<controller::Controller> Registry::make(const Mission& mission, RobotId self) {
  return make_controller(resolve(mission), mission, self);
}

std::unique_ptr<controller::Controller> make_controller(const Descriptor& d, const Mission& mission,
                                                        RobotId self) {
  if (d.make == nullptr) {
    throw InputError("<mission>", 0, no_controller_message(d.name, mission.descriptor));
  }
  check_params(d, mission.params);
  if (d.needs_shape && mission.shape.label_count() == 0) {
    throw InputError("<mission>", 0, "behaviour '" + std::string(d.name) + "' needs a shape");
  }
  std::unique_ptr<controller::Controller> c = d.make();
  if (!c) throw InputError("<mission>", 0, "behaviour '" + std::string(d.name) + "' made no controller");
  c->init(mission, self);
  return c;
}

}  // namespace swarmform::behaviour
