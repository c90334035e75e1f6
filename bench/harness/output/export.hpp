// Frame export for other tools: a backend's sampled frames as glTF 2.0 binary (.glb, for Blender,
// three.js and other viewers) or as NumPy arrays (.npz). docs/output-files.md describes both.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bench/harness/output/frame_stream.hpp"
#include "core/scene.hpp"
#include "core/weave.hpp"

namespace chainmail {

enum class ExportFormat { gltf, npz };

// "gltf" or "npz", each once; anything else is a UsageError naming `flag`
std::vector<ExportFormat> parse_export_formats(const std::vector<std::string>& names,
                                               const std::string& flag = "--export");
// ".glb" or ".npz"
const char* export_extension(ExportFormat format);

// what the files describe besides the frames
struct ExportSource {
  const Scene& scene;
  const Weave& weave;
  std::string backend;
};

// largest array an .npz holds (a zip without its 64-bit extension): 4 GiB
inline constexpr std::uint64_t kMaxNpzArrayBytes = 0xffffffffull;
// "" when `samples` frames of the scene fit the formats, else why not (names the sample count)
std::string export_size_refusal(const Weave& weave, long long samples);

// glTF 2.0 binary: one torus mesh shared by one animated node per ring, and a second scene with
// the first frame as one EXT_mesh_gpu_instancing node (docs/output-files.md says why both)
void write_glb(const ExportSource& source, const FrameSequence& frames, const std::string& path);

// NumPy .npz (a zip of .npy arrays, stored): t (F), position (F, N, 3), orientation (F, N, 4)
// as w, x, y, z, grid (N, 2), wire_radius, centre_radius
void write_npz(const ExportSource& source, const FrameSequence& frames, const std::string& path);

// every format for one backend into `folder`/<backend><extension>
void write_exports(const ExportSource& source, const FrameSequence& frames,
                   const std::vector<ExportFormat>& formats, const std::string& folder);

}  // namespace chainmail
