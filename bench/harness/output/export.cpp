// The export formats, and the .npz writer: a zip (stored, no compression) of .npy arrays, written
// array by array straight from the frames, so that memory stays one frame.
#include "bench/harness/output/export.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include "bench/harness/common/usage_error.hpp"

namespace chainmail {
namespace {

static_assert(std::endian::native == std::endian::little, ".npy '<' arrays are little-endian");

// CRC-32 (zip's, polynomial 0xedb88320), table built once
std::uint32_t crc32_update(std::uint32_t crc, const unsigned char* data, std::size_t bytes) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int bit = 0; bit < 8; ++bit) c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (std::size_t k = 0; k < bytes; ++k) crc = table[(crc ^ data[k]) & 0xff] ^ (crc >> 8);
  return ~crc;
}

// the .npy header (format 1.0) of a C-order array: magic, version, length, then the dict padded
// with spaces to a multiple of 64 bytes and ended by a newline
std::string npy_header(const char* descr, const std::vector<std::size_t>& shape) {
  std::string dims;
  for (std::size_t d : shape) dims += std::to_string(d) + ", ";
  // Python's tuples: (F, N, 3), (F,) and ()
  if (shape.size() > 1) dims.resize(dims.size() - 2);
  if (shape.size() == 1) dims.pop_back();
  std::string dict =
      std::string("{'descr': '") + descr + "', 'fortran_order': False, 'shape': (" + dims + "), }";
  const std::size_t unpadded = 10 + dict.size() + 1;
  dict.append((64 - unpadded % 64) % 64, ' ');
  dict.push_back('\n');
  std::string header("\x93NUMPY\x01\x00", 8);
  header.push_back(static_cast<char>(dict.size() & 0xff));
  header.push_back(static_cast<char>(dict.size() >> 8));
  return header + dict;
}

// `bytes` little-endian bytes of value; past the eighth, zeros (a shift by 64 or more is undefined)
void put(std::string& out, std::uint64_t value, int bytes) {
  for (int k = 0; k < bytes; ++k)
    out.push_back(k < 8 ? static_cast<char>((value >> (8 * k)) & 0xff) : '\0');
}

// a zip of stored entries written one after the other; each entry's size and CRC are patched
// into its local header when it ends
class ZipWriter {
 public:
  explicit ZipWriter(const std::string& path) : file_(std::fopen(path.c_str(), "wb")) {
    if (!file_) throw std::runtime_error("cannot write " + path);
  }
  void begin(const std::string& name) {
    entry_ = {name, static_cast<std::uint64_t>(std::ftell(file_.get())), 0, 0};
    write(local_header(entry_));
  }
  void write(const void* data, std::size_t bytes) {
    if (std::fwrite(data, 1, bytes, file_.get()) != bytes) throw std::runtime_error("write error");
  }
  void write(const std::string& bytes) { write(bytes.data(), bytes.size()); }
  // entry data: counted and checksummed
  void data(const void* bytes, std::size_t count) {
    entry_.crc = crc32_update(entry_.crc, static_cast<const unsigned char*>(bytes), count);
    entry_.size += count;
    if (entry_.size > kMaxNpzArrayBytes) throw std::runtime_error("npz entry over 4 GiB");
    write(bytes, count);
  }
  void end() {
    const long here = std::ftell(file_.get());
    std::fseek(file_.get(), static_cast<long>(entry_.offset), SEEK_SET);
    write(local_header(entry_));
    std::fseek(file_.get(), here, SEEK_SET);
    entries_.push_back(entry_);
  }
  // the central directory and its end record
  void close() {
    const auto start = static_cast<std::uint64_t>(std::ftell(file_.get()));
    std::string directory;
    for (const Entry& e : entries_) {
      put(directory, 0x02014b50, 4);
      put(directory, 20, 2);  // made by: version 2.0
      directory += fields(e);
      put(directory, 0, 2 + 2 + 2 + 2 + 4);  // extra, comment, disk, internal, external
      put(directory, e.offset, 4);
      directory += e.name;
    }
    write(directory);
    std::string end;
    put(end, 0x06054b50, 4);
    put(end, 0, 4);  // this disk, directory's disk
    put(end, entries_.size(), 2);
    put(end, entries_.size(), 2);
    put(end, directory.size(), 4);
    put(end, start, 4);
    put(end, 0, 2);
    write(end);
    if (std::fflush(file_.get()) != 0) throw std::runtime_error("write error");
  }

 private:
  struct Entry {
    std::string name;
    std::uint64_t offset, size;
    std::uint32_t crc;
  };
  struct Closer {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  // version needed, flags, method (0: stored), time, date (1980-01-01), crc, sizes, name length
  static std::string fields(const Entry& e) {
    std::string out;
    put(out, 20, 2);
    put(out, 0, 2);
    put(out, 0, 2);
    put(out, 0, 2);
    put(out, 0x21, 2);
    put(out, e.crc, 4);
    put(out, e.size, 4);
    put(out, e.size, 4);
    put(out, e.name.size(), 2);
    return out;
  }
  static std::string local_header(const Entry& e) {
    std::string out;
    put(out, 0x04034b50, 4);
    out += fields(e);
    put(out, 0, 2);  // extra
    return out + e.name;
  }
  std::unique_ptr<std::FILE, Closer> file_;
  Entry entry_{};
  std::vector<Entry> entries_;
};

// one array of the frames, frame by frame: `column(frame, ring, out)` writes a ring's values
template <int Width, class Column>
void frame_array(ZipWriter& zip, const FrameSequence& frames, int rings, const char* name,
                 Column column) {
  zip.begin(std::string(name) + ".npy");
  const std::string header =
      npy_header("<f8", {frames.count, static_cast<std::size_t>(rings), Width});
  zip.data(header.data(), header.size());
  RingFrame frame;
  std::vector<double> row(static_cast<std::size_t>(rings) * Width);
  for (std::size_t k = 0; k < frames.count; ++k) {
    if (!frames.read(k, frame)) throw std::runtime_error("cannot read frame " + std::to_string(k));
    for (int ring = 0; ring < rings; ++ring) column(frame, ring, &row[Width * ring]);
    zip.data(row.data(), row.size() * sizeof(double));
  }
  zip.end();
}

// a small array given whole
void whole_array(ZipWriter& zip, const char* name, const char* descr,
                 const std::vector<std::size_t>& shape, const void* data, std::size_t bytes) {
  zip.begin(std::string(name) + ".npy");
  const std::string header = npy_header(descr, shape);
  zip.data(header.data(), header.size());
  zip.data(data, bytes);
  zip.end();
}

}  // namespace

std::vector<ExportFormat> parse_export_formats(const std::vector<std::string>& names,
                                               const std::string& flag) {
  std::vector<ExportFormat> formats;
  for (const std::string& name : names) {
    ExportFormat format;
    if (name == "gltf")
      format = ExportFormat::gltf;
    else if (name == "npz")
      format = ExportFormat::npz;
    else
      throw UsageError(flag + ": unknown format '" + name + "' (gltf, npz)");
    if (std::find(formats.begin(), formats.end(), format) == formats.end())
      formats.push_back(format);
  }
  return formats;
}

const char* export_extension(ExportFormat format) {
  return format == ExportFormat::gltf ? ".glb" : ".npz";
}

std::string export_size_refusal(const Weave& weave, long long samples) {
  const double bytes = 4.0 * 8.0 * weave.size() * static_cast<double>(samples);  // orientation
  if (bytes <= static_cast<double>(kMaxNpzArrayBytes)) return "";
  return std::to_string(samples) + " samples of " + std::to_string(weave.size()) +
         " rings are over the 4 GiB an exported array may hold";
}

void write_npz(const ExportSource& source, const FrameSequence& frames, const std::string& path) {
  const int rings = source.weave.size();
  const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
  {
    ZipWriter zip(tmp);
    std::vector<double> times;
    frame_array<3>(zip, frames, rings, "position",
                   [&](const RingFrame& frame, int ring, double* out) {
                     if (ring == 0) times.push_back(frame.t);
                     for (int c = 0; c < 3; ++c) out[c] = frame.position(c, ring);
                   });
    frame_array<4>(zip, frames, rings, "orientation",
                   [](const RingFrame& frame, int ring, double* out) {
                     for (int c = 0; c < 4; ++c) out[c] = frame.orientation(c, ring);
                   });
    whole_array(zip, "t", "<f8", {times.size()}, times.data(), times.size() * sizeof(double));
    std::vector<std::int64_t> grid;
    for (const auto& ij : source.weave.grid) grid.insert(grid.end(), {ij[0], ij[1]});
    whole_array(zip, "grid", "<i8", {static_cast<std::size_t>(rings), 2}, grid.data(),
                grid.size() * sizeof(std::int64_t));
    const double a = source.scene.ring.wire_radius, c = source.scene.ring.centre_radius;
    whole_array(zip, "wire_radius", "<f8", {}, &a, sizeof a);
    whole_array(zip, "centre_radius", "<f8", {}, &c, sizeof c);
    zip.close();
  }
  std::filesystem::rename(tmp, path);
}

void write_exports(const ExportSource& source, const FrameSequence& frames,
                   const std::vector<ExportFormat>& formats, const std::string& folder) {
  std::filesystem::create_directories(folder);
  for (ExportFormat format : formats) {
    const std::string path = folder + "/" + source.backend + export_extension(format);
    if (format == ExportFormat::gltf)
      write_glb(source, frames, path);
    else
      write_npz(source, frames, path);
  }
}

}  // namespace chainmail
