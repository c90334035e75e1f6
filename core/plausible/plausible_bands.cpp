// The plausible model's sweeps, with the threads meeting at band edges instead of after every
// colour. A coloured sweep runs a dozen or more stages (the
// attachment lists, the edge colours, the diagonal colours), and a team that waits for all its
// threads after each stage waits for the slowest one a dozen times a sweep, 16 sweeps a step.
// Here each thread takes a run of bands through all stages and waits only for the two bands at
// the edges of its run, which its neighbours solve first in every stage: by the time it needs
// them they are usually done. Pairs of one stage share no ring, and pairs of different stages
// share rings only within a band or across a band edge, so each pair meets the very positions it
// meets in the coloured sweep: the result is the same bits, on any thread count.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>

#include "core/parallel.hpp"
#include "core/plausible/constraints.hpp"
#include "core/plausible/plausible.hpp"
#include "core/plausible/plausible_blocks.hpp"

namespace chainmail {
namespace {

// bands a sheet is cut into (fewer where the pairs reach farther); each thread's run takes two
// or more, so that its interior gives the neighbours time to finish the edge bands
constexpr int kBands = 16;

int band_of(const std::vector<int>& first_ring, int ring) {
  return static_cast<int>(std::upper_bound(first_ring.begin(), first_ring.end(), ring) -
                          first_ring.begin()) -
         1;
}

// reorders each colour's pairs by the band of their lower ring (a colour's pairs are independent:
// their order changes nothing) and adds one stage per colour, its pairs also as blocks of four
void add_colour_stages(SweepBands::Kind kind, std::vector<EdgeConstraint>& pairs,
                       const Colouring& colours, const std::vector<double>& inverse_mass,
                       SweepBands& bands) {
  auto band = [&](const EdgeConstraint& e) {
    return band_of(bands.first_ring, std::min(e.a, e.b));
  };
  for (int c = 0; c < colours.colours(); ++c) {
    const auto begin = pairs.begin() + colours.start[c], end = pairs.begin() + colours.start[c + 1];
    std::stable_sort(begin, end, [&](const EdgeConstraint& x, const EdgeConstraint& y) {
      return band(x) < band(y);
    });
    SweepBands::Stage stage;
    stage.kind = kind;
    auto at = begin;
    for (int k = 0; k <= bands.bands(); ++k) {
      while (at != end && band(*at) < k) ++at;
      stage.band_start.push_back(static_cast<int>(at - pairs.begin()));
    }
    stage.block_start.push_back(0);
    // (a serial colour's pairs may share rings, but a block's four lanes never do, and blocks
    // go in order)
    for (int k = 0; k < bands.bands(); ++k) {
      const std::vector<PairBlock> band = make_pair_blocks(pairs.data(), stage.band_start[k],
                                                           stage.band_start[k + 1], inverse_mass);
      stage.blocks.insert(stage.blocks.end(), band.begin(), band.end());
      stage.block_start.push_back(static_cast<int>(stage.blocks.size()));
    }
    bands.stages.push_back(std::move(stage));
  }
}

// a band's count of finished stages, on a cache line of its own (threads poll their neighbours')
struct alignas(kCacheLine) BandProgress {
  std::atomic<int> stages{0};
};

// waits until `band` has finished `stages` stages: a short spin (the usual case, its thread is a
// band or so behind), then asleep until the band's thread reports (that thread may be waiting for
// a core on a busy machine: spinning or yielding here would take the core it needs)
void wait_for(const BandProgress& band, int stages) {
  constexpr int kSpins = 2000;
  for (int spin = 0; spin < kSpins; ++spin) {
    if (band.stages.load(std::memory_order_acquire) >= stages) return;
  }
  for (int done = band.stages.load(std::memory_order_acquire); done < stages;
       done = band.stages.load(std::memory_order_acquire)) {
    band.stages.wait(done, std::memory_order_acquire);
  }
}

// records that `band` has finished `stages` stages and wakes a thread asleep on it
void report(BandProgress& band, int stages) {
  band.stages.store(stages, std::memory_order_release);
  band.stages.notify_all();
}

}  // namespace

void PlausibleSim::build_sweep_bands() {
  model_.bands = SweepBands{};
  const int n = static_cast<int>(model_.weave.size());
  // the farthest a pair reaches in ring indices: a band is at least that wide
  int reach = 1;
  for (const auto* pairs : {&model_.edges, &model_.diagonals}) {
    for (const EdgeConstraint& e : *pairs) reach = std::max(reach, std::abs(e.a - e.b));
  }
  const int width = std::max(reach, (n + kBands - 1) / kBands);
  // a list that overflowed its colours has pairs sharing rings in one stage, solved in order:
  // one band, one thread
  const bool serial = model_.edge_colours.serial_tail || model_.diagonal_colours.serial_tail;
  const int count = serial ? 1 : std::max(1, (n + width - 1) / width);
  SweepBands& bands = model_.bands;
  for (int k = 0; k <= count; ++k) bands.first_ring.push_back(k == count ? n : k * width);
  // the attachments first (each list a stage: it holds a ring once); they move only their ring
  // (a pin never moves), so each goes with its ring's band
  for (int list = 0; list < static_cast<int>(model_.attachments.size()); ++list) {
    std::vector<PinAttachment>& items = model_.attachments[list];
    if (items.empty()) continue;
    // by ring, hence by band, and in runs of consecutive rings for the vector sweep (a list's
    // projections are independent: their order changes nothing)
    std::sort(items.begin(), items.end(),
              [](const PinAttachment& x, const PinAttachment& y) { return x.ring < y.ring; });
    SweepBands::Stage stage;
    stage.kind = SweepBands::Kind::attachments;
    stage.list = list;
    size_t at = 0;
    for (int k = 0; k <= count; ++k) {
      while (at < items.size() && band_of(bands.first_ring, items[at].ring) < k) ++at;
      stage.band_start.push_back(static_cast<int>(at));
    }
    stage.block_start.push_back(0);
    for (int k = 0; k < count; ++k) {
      const std::vector<AttachmentBlock> band =
          make_attachment_blocks(items.data(), stage.band_start[k], stage.band_start[k + 1]);
      stage.attachment_blocks.insert(stage.attachment_blocks.end(), band.begin(), band.end());
      stage.block_start.push_back(static_cast<int>(stage.attachment_blocks.size()));
    }
    for (const PinAttachment& item : items) stage.reach.push_back(item.max_distance);
    bands.stages.push_back(std::move(stage));
  }
  add_colour_stages(SweepBands::Kind::edges, model_.edges, model_.edge_colours, model_.inverse_mass,
                    bands);
  add_colour_stages(SweepBands::Kind::diagonals, model_.diagonals, model_.diagonal_colours,
                    model_.inverse_mass, bands);
}

SweepViolation PlausibleSim::sweep_links() {
  auto scope = profile_.scope("constraints");
  const SweepBands& bands = model_.bands;
  const int count = bands.bands();
  const int stages = static_cast<int>(bands.stages.size());
  std::vector<BandProgress> progress(count);
  // each thread's run needs two bands or more (the step's threads are already as many as its
  // rings are worth)
  const int team = parallel_loops_available() ? std::max(1, std::min(threads_, count / 2)) : 1;
  std::vector<double> busy(team, 0.0);  // s, each thread's time solving (not waiting)
  // a new team size starts from an even split
  auto split_for = [&](int members) {
    if (static_cast<int>(band_split_.size()) != members + 1 || band_split_.back() != count) {
      band_split_.resize(members + 1);
      for (int t = 0; t <= members; ++t) band_split_[t] = count * t / members;
    }
  };
  // thread `me`'s run of bands [first, last) through every stage: the largest violations it met
  auto run = [&](int me, int first, int last) {
    SweepViolation met;
    using Clock = std::chrono::steady_clock;
    const Clock::time_point start = Clock::now();
    Clock::duration waiting{};
    // the edge bands first, where the neighbouring runs wait, then the interior
    std::vector<int> order = {last - 1};
    if (first < last - 1) order.push_back(first);
    for (int k = first + 1; k < last - 1; ++k) order.push_back(k);
    for (int s = 0; s < stages; ++s) {
      for (int k : order) {
        // a neighbour's pairs of an earlier stage move this band's rings (the band below) or
        // rings this band's pairs move (the band above): it must have finished them
        const bool below = k == first && k > 0, above = k == last - 1 && k + 1 < count;
        if (below || above) {
          const Clock::time_point wait_start = Clock::now();
          if (below) wait_for(progress[k - 1], s);
          if (above) wait_for(progress[k + 1], s);
          waiting += Clock::now() - wait_start;
        }
        const double found = solve_stage_band(bands.stages[s], k);  // m
        double& kind =
            bands.stages[s].kind == SweepBands::Kind::attachments ? met.attachments : met.links;
        kind = std::max(kind, found);
        if (bands.stages[s].kind == SweepBands::Kind::edges) met.edges = std::max(met.edges, found);
        // only the run's edge bands are waited for
        if (k == first || k == last - 1) report(progress[k], s + 1);
      }
    }
    busy[me] = std::chrono::duration<double>(Clock::now() - start - waiting).count();
    return met;
  };
  int members = 1;
  SweepViolation met;
  if (team == 1) {
    // one thread: the run here, outside the OpenMP runtime (parallel_for)
    split_for(1);
    met = run(0, 0, count);
  } else {
    double attachments = 0.0, links = 0.0, edges = 0.0;  // m
#pragma omp parallel num_threads(team) reduction(max : attachments, links, edges)
    {
      // this thread's run of bands, from the team it got (which may be smaller than asked)
      int me = 0;
#if defined(CHAINMAIL_HAS_OPENMP)
#pragma omp single
      members = omp_get_num_threads();
      me = omp_get_thread_num();
#endif
#pragma omp single
      split_for(members);
      const SweepViolation mine = run(me, band_split_[me], band_split_[me + 1]);
      attachments = mine.attachments;
      links = mine.links;
      edges = mine.edges;
    }
    met = {attachments, links, edges};
  }
  busy.resize(members);
  balance_band_split(busy);
  return met;
}

void PlausibleSim::balance_band_split(const std::vector<double>& busy) {
  // each boundary moves a band toward the thread on its side that worked less, where the
  // difference exceeds the time of a band (so the split settles instead of swinging); each run
  // keeps two bands or more, its edges to be waited for and an interior to work on meanwhile
  const int members = static_cast<int>(busy.size());
  // the busy times smoothed over sweeps (one sweep's vary by a quarter); a move hands a band's
  // time from one thread to the other
  if (static_cast<int>(band_busy_.size()) != members) band_busy_.assign(busy.begin(), busy.end());
  for (int t = 0; t < members; ++t) band_busy_[t] = 0.875 * band_busy_[t] + 0.125 * busy[t];
  for (int t = 1; t < members; ++t) {
    const double low = band_busy_[t - 1], high = band_busy_[t];  // s
    const int below = band_split_[t] - band_split_[t - 1],
              above = band_split_[t + 1] - band_split_[t];
    const double band = (low + high) / (below + above);  // s, a band's mean time
    int move = 0;
    if (low - high > band && below > 2) move = -1;
    if (high - low > band && above > 2) move = 1;
    if (move == 0) continue;
    band_split_[t] += move;
    band_busy_[t - 1] += move * band;
    band_busy_[t] -= move * band;
  }
}

double PlausibleSim::solve_stage_band(const SweepBands::Stage& stage, int band) {
  double* const x = state_.position.data();            // (3 n) m
  const double* const w = model_.inverse_mass.data();  // (n) 1/kg
  const int first = stage.block_start[band];           // the band's first block
  if (stage.kind == SweepBands::Kind::attachments) {
    const PinAttachment* const list = model_.attachments[stage.list].data();
    return sweep_attachment_blocks(x, list, stage.reach.data(),
                                   stage.attachment_blocks.data() + first,
                                   stage.block_start[band + 1] - first, vector_sweeps_);
  }
  const EdgeConstraint* const pairs =
      (stage.kind == SweepBands::Kind::edges ? model_.edges : model_.diagonals).data();
  return sweep_pair_blocks(x, w, pairs, stage.blocks.data() + first,
                           stage.block_start[band + 1] - first, vector_sweeps_);
}

}  // namespace chainmail
