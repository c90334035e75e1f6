// The frame-stream and reference-cache reader: the first byte gives the ring count (1 to 64),
// the rest is the file. A stream that is not whole records of its header is refused (nullopt);
// one that opens reads every record without reading outside it.
#include <cmath>

#include "bench/harness/output/frame_stream.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace chainmail;
  if (size == 0) return 0;
  const int rings = 1 + data[0] % 64;
  const std::string path = fuzz::scratch() + "/stream.frames";
  fuzz::write(path, std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  std::optional<FrameReader> reader = FrameReader::open(path, rings);
  if (!reader) return 0;
  RingFrame frame;
  frame.resize(rings);
  for (std::size_t k = 0; k < reader->count() && k < 64; ++k) {
    reader->read(k, frame);
    const std::size_t near = reader->nearest(reader->time(k));
    if (near >= reader->count()) __builtin_trap();
  }
  if (reader->count() > 0 && reader->nearest(std::nan("")) >= reader->count()) __builtin_trap();
  return 0;
}
