// The registry of behaviours a process may run: the built-ins (added by their library, robot_agent/controller
// builtins.hpp) and the shared-library plug-ins it loaded. robot_agent, world_server and the in-process
// harness all make controllers through it, so both modes run the same code.
//
// A behaviour may also be described by a JSON file (descriptor_file.hpp): the registry keeps what it loaded
// for the whole process; such a behaviour has no controller (its agents run an --exec program).
//
// Safety: a plug-in is native code. A registry loads one only from the folders it was given (its process's
// own command line and environment, never a path that arrived on the wire alone): the path is made canonical
// (symbolic links resolved) and must then lie under one of those folders, canonical too; anything else is
// refused with a PluginError naming the path and the folders. A loaded library is never unloaded: its
// descriptor and code stay valid for the whole process.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "behaviour/descriptor.hpp"
#include "behaviour/descriptor_file.hpp"
#include "common/mission.hpp"

namespace swarmform::behaviour {

class PluginError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The environment variable holding extra plug-in folders, ':'-separated.
inline constexpr const char* kPluginPathVariable = "SWARMFORM_PLUGIN_PATH";

// Why a behaviour described by a file cannot be run in-process: "behaviour 'x' is described by x.json and has
// no controller: its agents run it with robot_agent --exec / swarm run --exec". `file`: the descriptor's path
// (its name is said), or empty when unknown ("a descriptor file").
std::string no_controller_message(std::string_view behaviour, const std::string& file);

// A controller of behaviour `d` for robot `self`: the mission's parameters checked against d's table, the
// shape required when d needs one, then made and initialised. Throws InputError for a bad mission, and for
// a behaviour described by a file (no_controller_message).
std::unique_ptr<controller::Controller> make_controller(const Descriptor& d, const Mission& mission,
                                                        RobotId self);

class Registry {
 public:
  // `folders`: where plug-ins may be loaded from (to which the environment's SWARMFORM_PLUGIN_PATH folders
  // are added by add_folders_from_environment).
  explicit Registry(std::vector<std::filesystem::path> folders = {});

  // A built-in behaviour (with a make). Throws std::logic_error when the name is taken.
  void add(const Descriptor& d);
  // The behaviour described by the JSON file at `path` (loaded once; later calls return the same
  // descriptor), kept for the life of the registry. Throws InputError(path, 0, ...) for a bad file or a name
  // already registered from elsewhere.
  const Descriptor& load_descriptor(const std::string& path);
  void add_folder(const std::filesystem::path& folder);
  void add_folders_from_environment();

  // A registered behaviour by name (built-in or already loaded), or nullptr.
  const Descriptor* find(std::string_view name) const;
  // The plug-in at `path` (loaded once; later calls return the same descriptor). Throws PluginError when the
  // path lies outside the plug-in folders, cannot be opened, exports no descriptor, was built against
  // another API version, or names a behaviour that is already registered from elsewhere.
  const Descriptor& load_plugin(const std::string& path);
  // The mission's behaviour: its plug-in when mission.plugin is set (whose name must be mission.behaviour),
  // else the registered one of that name. A mission naming a descriptor file resolves only to that
  // behaviour when this registry loaded the file (the world's); an agent does not load it, and is told
  // no_controller_message. Throws InputError("<mission>", 0, ...) when there is none.
  const Descriptor& resolve(const Mission& mission);
  // resolve, check the mission's parameters against the behaviour's table, make and init a controller.
  // Throws InputError for a bad mission, PluginError for a refused plug-in.
  std::unique_ptr<controller::Controller> make(const Mission& mission, RobotId self);

  // "paper, random_walk": the registered names, for messages.
  std::string names() const;
  const std::vector<std::filesystem::path>& folders() const { return folders_; }
  // "/a, /b" or "none": the plug-in folders, for messages.
  std::string folders_text() const;

 private:
  std::vector<std::filesystem::path> folders_;  // canonical
  std::map<std::string, const Descriptor*, std::less<>> by_name_;
  std::map<std::string, const Descriptor*> by_path_;  // canonical path -> the plug-in's descriptor
  // canonical path -> the behaviour a descriptor file describes; never freed (descriptors point into it)
  std::map<std::string, std::unique_ptr<const DescribedBehaviour>> described_;
};

}  // namespace swarmform::behaviour
