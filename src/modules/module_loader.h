#pragma once
// Finds and loads mvox's modules: shared libraries holding the only code that links a heavy
// library (OpenCV's image codecs, GDCM, libtiff with its codec libraries, OpenCV's highgui and
// Qt), so that a run loads one only when its input or outputs need it. A raw volume, NRRD,
// MetaImage or PNG run, `--help`, `phantom` and `demo` load none, and a TIFF run libtiff's
// alone: that is most of mvox's start-up time and memory saved.
//
// Each module has a C interface (modules/*/..._api.h) with a version function, so that a module
// from another build is refused instead of being called with the wrong arguments; C, because
// nothing that two builds could lay out differently (exceptions included) may cross a dlopen
// boundary. A module stays loaded until the process ends (no dlclose: Qt and GDCM leave threads
// and exit handlers pointing into their code).
#include <mutex>
#include <string>
#include <vector>

namespace mvox {

// One module, as mvox names it in messages.
struct ModuleName {
  const char* file;     // "libmvox_dicom_codecs.so"
  const char* what;     // "DICOM module (GDCM)", as in "cannot load the DICOM module (GDCM)"
  const char* install;  // what installs the library it links, for the message when it is missing
};

// The directories searched for modules, in order:
//   1. when MVOX_MODULE_PATH is set (directories separated by ':'), those and no others: for
//      tests, relocated installs, and a user who wants to see that a run needs no module;
//   2. the directory of the file holding mvox's host code: the mvox executable, or the program,
//      shared library or Python module that links mvox::host; the build puts the modules beside
//      the mvox executable;
//   3. that directory's ../lib/mvox (MVOX_MODULE_RELATIVE_DIR), where `cmake --install` puts
//      them relative to the executable, so that an installed tree can be moved or installed
//      with --prefix;
//   4. MVOX_MODULE_INSTALL_DIR, the same place as configured (PREFIX/lib/mvox).
std::vector<std::string> module_directories();

// Loads `module` (once per process; later calls return the same handle) and checks that its
// `<prefix>_api_version` function returns `api_version`. Returns the handle for
// module_symbol(), or nullptr with a one-line reason in *why_not (no final period), which names
// the module, where it was looked for or why it did not load, and how to install what it
// needs. Safe to call from several threads.
void* load_module(const ModuleName& module, const char* version_symbol, int api_version,
                  std::string* why_not);

// The address of `symbol` in a module load_module() returned, or nullptr.
void* module_symbol(void* handle, const char* symbol);

// load_module() for a caller that reads `subject` (an input or an output): throws
// mvox::Error(subject, reason) instead of returning nullptr.
void* require_module(const ModuleName& module, const char* version_symbol, int api_version,
                     const std::string& subject);

[[noreturn]] void throw_missing_function(const ModuleName& module, const char* symbol,
                                         const std::string& subject);

// Sets *function to `symbol` in `handle`, a module require_module() loaded; throws
// mvox::Error(subject, "the WHAT lacks SYMBOL") when the module has no such function.
template <class Function>
void resolve_function(void* handle, const char* symbol, Function** function,
                      const ModuleName& module, const std::string& subject) {
  *function = reinterpret_cast<Function*>(module_symbol(handle, symbol));
  if (*function == nullptr) throw_missing_function(module, symbol, subject);
}

// The table of `module`'s functions that fill(handle, table) resolves (with resolve_function),
// loaded with the module at the first call and returned by every later one; or
// mvox::Error(subject, why not), after which a later call tries again. Safe to call from
// several threads. Each call site has its own table: the statics belong to this
// instantiation, and `Fill` is the caller's own lambda.
template <class Table, class Fill>
const Table& module_functions(const ModuleName& module, const char* version_symbol, int api_version,
                              const std::string& subject, Fill fill) {
  static std::mutex mutex;
  static Table loaded;
  static bool ready = false;
  const std::lock_guard<std::mutex> lock(mutex);
  if (!ready) {
    void* handle = require_module(module, version_symbol, api_version, subject);
    Table functions;
    fill(handle, functions);
    loaded = functions;
    ready = true;
  }
  return loaded;
}

// The modules loaded so far, as the files they were loaded from, in the order of loading.
std::vector<std::string> loaded_modules();

}  // namespace mvox
