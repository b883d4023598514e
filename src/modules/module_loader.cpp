#include "modules/module_loader.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <mutex>

#include "error.h"

namespace mvox {
namespace {

std::mutex g_mutex;
std::map<std::string, void*> g_loaded;  // by module file name
std::vector<std::string> g_loaded_paths;

std::string dl_error_text() {
  const char* text = dlerror();
  return text != nullptr ? text : "unknown dlopen error";
}

// The directory of the file that holds this function: the executable when mvox::host is linked
// into it statically, or the shared library or Python module that links it.
std::string own_directory() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&own_directory), &info) == 0 || info.dli_fname == nullptr)
    return "";
  std::string file = info.dli_fname;
  // The main executable is reported by the name it was started with (argv[0]): a bare name found
  // on PATH, or a symbolic link elsewhere. The kernel knows its real path; any other file's name
  // is resolved through its links.
  if (file.find('/') == std::string::npos) {
    char path[4096];
    const ssize_t length = readlink("/proc/self/exe", path, sizeof path - 1);
    if (length <= 0) return "";
    file.assign(path, static_cast<std::size_t>(length));
  } else if (char* real = realpath(file.c_str(), nullptr)) {
    file = real;
    std::free(real);
  }
  const std::size_t slash = file.rfind('/');
  return slash == std::string::npos ? "" : file.substr(0, slash);
}

std::string joined(const std::vector<std::string>& directories) {
  std::string text;
  for (const std::string& directory : directories) {
    if (!text.empty()) text += ", ";
    text += directory;
  }
  return text;
}

}  // namespace

std::vector<std::string> module_directories() {
  std::vector<std::string> directories;
  const char* path = std::getenv("MVOX_MODULE_PATH");
  if (path != nullptr && path[0] != '\0') {
    std::string list = path;
    std::size_t start = 0;
    while (start <= list.size()) {
      std::size_t end = list.find(':', start);
      if (end == std::string::npos) end = list.size();
      if (end > start) directories.push_back(list.substr(start, end - start));
      start = end + 1;
    }
    return directories;
  }
  const std::string own = own_directory();
  if (!own.empty()) {
    directories.push_back(own);
#ifdef MVOX_MODULE_RELATIVE_DIR
    // An installed mvox, wherever its prefix was moved: PREFIX/bin/../lib/mvox.
    directories.push_back(own + "/" + MVOX_MODULE_RELATIVE_DIR);
#endif
  }
#ifdef MVOX_MODULE_INSTALL_DIR
  if (std::find(directories.begin(), directories.end(), MVOX_MODULE_INSTALL_DIR) ==
      directories.end())
    directories.push_back(MVOX_MODULE_INSTALL_DIR);
#endif
  return directories;
}

void* load_module(const ModuleName& module, const char* version_symbol, int api_version,
                  std::string* why_not) {
  std::lock_guard<std::mutex> lock(g_mutex);
  const auto known = g_loaded.find(module.file);
  if (known != g_loaded.end()) return known->second;

  const std::vector<std::string> directories = module_directories();
  std::string found;
  for (const std::string& directory : directories) {
    const std::string candidate = directory + "/" + module.file;
    if (access(candidate.c_str(), F_OK) == 0) {
      found = candidate;
      break;
    }
  }
  const std::string cannot = std::string("cannot load the ") + module.what + " " + module.file;
  if (found.empty()) {
    *why_not = cannot + ": it is in none of " +
               (directories.empty() ? std::string("the directories (MVOX_MODULE_PATH is empty)")
                                    : joined(directories)) +
               "; build mvox with " + module.install + ", or install it with cmake --install";
    return nullptr;
  }
  void* handle = dlopen(found.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const std::string reason = dl_error_text();
    // A library the module links is missing: say which to install. Any other reason (another
    // architecture, a damaged file, permissions) is the dynamic loader's own.
    const bool library_missing = reason.find("cannot open shared object file") != std::string::npos;
    *why_not = cannot + " from " + found + ": " + reason +
               (library_missing ? "; install " + std::string(module.install) : "");
    return nullptr;
  }
  // A module that fails a check stays loaded but unused (see the header on dlclose).
  const auto version = reinterpret_cast<int (*)()>(dlsym(handle, version_symbol));
  if (version == nullptr) {
    *why_not = cannot + ": " + found + " lacks " + version_symbol + " (not an mvox module?)";
    return nullptr;
  }
  if (version() != api_version) {
    *why_not = cannot + ": " + found + " has interface version " + std::to_string(version()) +
               ", this mvox needs " + std::to_string(api_version) +
               " (a module of another build: rebuild or reinstall mvox)";
    return nullptr;
  }
  g_loaded[module.file] = handle;
  g_loaded_paths.push_back(found);
  return handle;
}

void* module_symbol(void* handle, const char* symbol) { return dlsym(handle, symbol); }

void* require_module(const ModuleName& module, const char* version_symbol, int api_version,
                     const std::string& subject) {
  std::string why_not;
  void* handle = load_module(module, version_symbol, api_version, &why_not);
  if (handle == nullptr) throw Error(subject, why_not);
  return handle;
}

void throw_missing_function(const ModuleName& module, const char* symbol,
                            const std::string& subject) {
  throw Error(subject, std::string("the ") + module.what + " " + module.file + " lacks " + symbol);
}

std::vector<std::string> loaded_modules() {
  std::lock_guard<std::mutex> lock(g_mutex);
  return g_loaded_paths;
}

}  // namespace mvox
