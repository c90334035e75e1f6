#include "bench/harness/output/frame_stream.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>

namespace chainmail {
namespace {

constexpr char kMagic[8] = {'C', 'M', 'F', 'R', 'M', '0', '0', '1'};
constexpr long kHeaderBytes = 32;  // magic, rings, doubles per record, reserved

long long record_doubles(int rings) {
  return 1 + 7LL * rings;
}  // t, xyz, wxyz

}  // namespace

FrameWriter::FrameWriter(const std::string& path, int rings)
    : file_(std::fopen(path.c_str(), "wb")), rings_(rings), record_(record_doubles(rings)) {
  if (!file_) return;
  const long long header[3] = {rings, record_doubles(rings), 0};
  failed_ = std::fwrite(kMagic, 1, 8, file_.get()) != 8 ||
            std::fwrite(header, sizeof header, 1, file_.get()) != 1;
}

void FrameWriter::append(const RingFrame& frame) {
  if (!ok() || frame.size() != rings_) {
    failed_ = true;
    return;
  }
  record_[0] = frame.t;
  std::memcpy(record_.data() + 1, frame.position.data(), sizeof(double) * 3 * rings_);
  std::memcpy(record_.data() + 1 + 3 * rings_, frame.orientation.data(),
              sizeof(double) * 4 * rings_);
  failed_ =
      std::fwrite(record_.data(), sizeof(double), record_.size(), file_.get()) != record_.size();
}

bool FrameWriter::close() {
  if (!file_) return false;
  const bool flushed = std::fflush(file_.get()) == 0;
  file_.reset();
  return flushed && !failed_;
}

std::optional<FrameReader> FrameReader::open(const std::string& path, int rings) {
  struct stat info {};
  // only a regular file: a FIFO or a device named as a cache entry must not block or be read
  if (::stat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) return std::nullopt;
  std::shared_ptr<std::FILE> file(std::fopen(path.c_str(), "rb"), [](std::FILE* f) {
    if (f) std::fclose(f);
  });
  if (!file) return std::nullopt;
  char magic[8];
  long long header[3] = {0, 0, 0};
  if (std::fread(magic, 1, 8, file.get()) != 8 || std::memcmp(magic, kMagic, 8) != 0 ||
      std::fread(header, sizeof header, 1, file.get()) != 1) {
    return std::nullopt;
  }
  // the header must describe this weave, and the file size must be whole records of it
  const long long record_bytes = sizeof(double) * record_doubles(rings);
  const long long body = static_cast<long long>(info.st_size) - kHeaderBytes;
  if (header[0] != rings || header[1] != record_doubles(rings) || body <= 0 ||
      body % record_bytes != 0) {
    return std::nullopt;
  }
  FrameReader reader;
  reader.file_ = file;
  reader.rings_ = rings;
  reader.times_.resize(body / record_bytes);
  for (std::size_t k = 0; k < reader.times_.size(); ++k) {
    if (std::fseek(file.get(), kHeaderBytes + static_cast<long>(k * record_bytes), SEEK_SET) != 0 ||
        std::fread(&reader.times_[k], sizeof(double), 1, file.get()) != 1) {
      return std::nullopt;
    }
  }
  return reader;
}

std::size_t FrameReader::nearest(double t) const {
  std::size_t best = 0;
  for (std::size_t k = 1; k < times_.size(); ++k) {
    if (std::abs(times_[k] - t) < std::abs(times_[best] - t)) best = k;
  }
  return best;
}

bool FrameReader::read(std::size_t k, RingFrame& frame) const {
  if (k >= times_.size()) return false;
  const long record_bytes = static_cast<long>(sizeof(double) * record_doubles(rings_));
  frame.resize(rings_);
  frame.velocity.setZero();
  std::FILE* f = file_.get();
  return std::fseek(f, kHeaderBytes + static_cast<long>(k) * record_bytes, SEEK_SET) == 0 &&
         std::fread(&frame.t, sizeof(double), 1, f) == 1 &&
         std::fread(frame.position.data(), sizeof(double), 3 * rings_, f) == 3u * rings_ &&
         std::fread(frame.orientation.data(), sizeof(double), 4 * rings_, f) == 4u * rings_;
}

bool copy_stream(const std::string& from, const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec, ignored;
  const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
  fs::copy_file(from, tmp, fs::copy_options::overwrite_existing, ec);
  if (!ec) fs::rename(tmp, path, ec);
  if (ec) fs::remove(tmp, ignored);
  return !ec;
}

FrameSequence stream_sequence(FrameReader reader) {
  FrameSequence sequence;
  sequence.count = reader.count();
  sequence.read = [reader = std::move(reader)](std::size_t k, RingFrame& frame) {
    return reader.read(k, frame);
  };
  return sequence;
}

}  // namespace chainmail
