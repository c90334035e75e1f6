// Where chainmail reads its data at run time: the bench scene files, the shaders and the sweep
// plot script. An installed binary (<prefix>/bin/chainmail) reads <prefix>/share/chainmail; a
// binary in its build tree reads the source tree it was built from; $CHAINMAIL_DATA_DIR names
// either kind of folder and wins over both.
#pragma once

#include <string>

namespace chainmail {

// a data folder in one of its two layouts:
//   installed:   scenes/, shaders/, plot_sweep.py
//   source tree: bench/scenes/, shaders/, bench/plot_sweep.py
struct DataDir {
  std::string root;          // "" when none was found
  bool source_tree = false;  // the source layout

  // each throws UsageError (bad input: exit 2) when no data folder was found
  std::string scenes() const;  // the folder of the bench scene files
  std::string shaders() const;
  std::string plot_script(const std::string& name) const;  // plot_sweep.py
};

// `root` in the layout it has: a source tree holds bench/scenes/
DataDir data_dir_at(const std::string& root);

// the first of: `env` when set and not empty; `installed` (the install's data folder, found
// from the binary's path) when it holds scenes/; `source` (the tree the binary was built from)
// when it holds bench/scenes/; else none
DataDir find_data_dir(const char* env, const std::string& installed, const std::string& source);

// find_data_dir for this process: $CHAINMAIL_DATA_DIR, <bin>/../share/chainmail beside the
// running binary, the source tree of the build
const DataDir& data_dir();

// the shader folder for --render: shaders/ beside the binary (a build tree copies them there),
// else $CHAINMAIL_SHADER_DIR, else data_dir().shaders(); the first that is a folder ("" when
// none is, and the renderer names what it searched)
std::string render_shader_dir();

// the report page's static files (index.html, scripts, styles, three.js): report/ beside the
// binary (a build tree copies it there), else the data folder's report/ ("" when neither is)
std::string report_page_dir();

}  // namespace chainmail
