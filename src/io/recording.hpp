#pragma once
// Recordings of a run for the web viewer (docs/recording.md fixes the format): the scene's shapes once, then
// per step the body poses, the constraint graph (docs/design.md#graph) and one or more partition "channels"
// (docs/design.md#partition, #refine) with their interface edges, and the step's statistics
// (docs/design.md#contracts). Little-endian binary, gzip-compressed as a whole so the browser can inflate it
// with DecompressionStream.
#include "io/run_params.hpp"
#include "partition/partition.hpp"

#include <rbpart/params.hpp>
#include <rbpart/scene.hpp>
#include <rbpart/world.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace rbpart {

constexpr std::uint32_t kRecordingVersion = 1;
// "RBPREC" then CR LF, so that a text-mode transfer that rewrites line ends is detected.
constexpr std::array<char, 8> kRecordingMagic = {'R', 'B', 'P', 'R', 'E', 'C', '\r', '\n'};

// The per-step statistics a frame carries, in order, named as the stats CSV columns (without
// "step", which the frame holds itself).
extern const std::vector<std::string> kRecordedStats;

// A partition channel beyond the run's own: partitioner, refiner and their parameters. The caller
// partitions each step's graph for it (partition_and_refine); the writer only stores the result.
// Name as the viewer lists it: "mindp", "mix+fm" (refiner None adds nothing).
std::string channel_name(const PartitionParams& params);
// "mindp,mix+fm,bfs" -> one configuration each, with `base`'s nmax and thresholds. Throws InputError
// on an empty item, an unknown partitioner or refiner, or partitioner none.
std::vector<PartitionParams> parse_channel_list(const std::string& list, const PartitionParams& base);

// An extra channel's partition of one step's graph and its quality, whose partition_ms and
// refine_ms are recorded.
struct ChannelPartition {
  Partition partition;
  PartitionQuality quality;
};

// Streams a recording into `path`: construct before the run, write_step() after every step,
// finish() at the end. The file appears only when finish() succeeds (AtomicFile).
class RecordingWriter {
 public:
  // Takes the shapes and starting poses from `world` (before its first step). `run_channel` names
  // the run's own partition (World::partition()), channel 0; `extra` the channels after it, whose
  // partitions write_step() is given. Throws InputError if `path` cannot be created.
  RecordingWriter(const std::string& path, const World& world, const ParamList& params,
                  const std::string& run_channel, std::vector<PartitionParams> extra);
  ~RecordingWriter();
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;

  // Records `world` as it is after the step that returned `stats`, with `extra`: the step's
  // partition of each extra channel, in the constructor's order.
  void write_step(const World& world, const StepStats& stats, const std::vector<ChannelPartition>& extra);
  // Ends the stream (the trailer holds the frame count) and commits the file.
  void finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A recording read back (for `rbpart view`/`snapshot` to validate a file, and for tests).
struct RecordedBody {
  Shape shape;           // vertices as stored (float precision)
  std::vector<std::uint32_t> face_offsets, face_indices;  // convex: hull faces (geometry/hull.hpp's HullFaces)
  bool is_static = false;
  float mass = 0;                // kg (0 for static bodies)
  std::array<float, 7> pose{};  // shape frame at the start: x y z, quaternion w x y z
  std::array<float, 3> com{};   // centre of mass in the shape frame
};

struct RecordedChannel {
  std::uint32_t parts = 0, edge_cut = 0, interface_rows = 0, interface_bodies = 0;
  float partition_ms = 0, refine_ms = 0;
  std::vector<std::uint32_t> part_of;      // node -> part id
  std::vector<std::uint8_t> interface;     // one bit per edge, edge e in byte e/8, bit e%8
  bool is_interface(std::size_t e) const { return (interface[e >> 3] >> (e & 7)) & 1; }
};

struct RecordedFrame {
  int step = 0;
  double time = 0;
  std::vector<double> stats;   // kRecordedStats order (the header's "stats" list)
  std::vector<float> poses;    // 7 per node (dynamic body): x y z, w x y z
  std::vector<std::uint32_t> edge_u, edge_v;          // u < v, sorted
  std::vector<std::uint16_t> edge_weight, edge_rows;  // constraints and rows between u and v
  std::vector<RecordedChannel> channels;
};

struct Recording {
  nlohmann::json meta;  // the header's JSON: scene, dt, gravity, params, channels, stats, ...
  std::vector<RecordedBody> bodies;
  std::vector<int> body_of;  // node -> body: the dynamic bodies in scene order
  std::vector<RecordedFrame> frames;
  std::vector<std::string> channel_names() const;
};

// Reads and validates a whole recording. Throws InputError naming `path` and the problem (not
// gzip, bad magic, unsupported version, truncated, inconsistent sizes).
Recording read_recording(const std::string& path);
// As read_recording, from the compressed bytes.
Recording parse_recording(const std::string& gzip_bytes, const std::string& name);

}  // namespace rbpart
