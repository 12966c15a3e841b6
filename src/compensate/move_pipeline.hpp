#pragma once
// Batching and the worker thread, the job's second stage. The interpreter's thread fills a
// batch of moves while those before it are compensated on the worker thread (on one
// thread: each batch is compensated in line once filled), then the compensated batches are
// handed to the writer here, in program order; so the compensator sees the same moves in
// the same order either way, and the output is the same for one thread and two.
#include <algorithm>
#include <array>
#include <cstddef>
#include <deque>
#include <functional>
#include <memory>

#include "ccomp/compensate/work_split.hpp"
#include "ccomp/util/parallel.hpp"
#include "move_solver.hpp"
#include "move_task.hpp"

namespace ccomp::compensate {

class MovePipeline {
 public:
  /// How the moves are cut into batches: at most `moves` moves and about `points`
  /// compensated points a batch (arcs' chords, long moves' checks, as the reader foresees
  /// them: a program of full circles at 1 um gives thousands of points a move, and memory
  /// must not grow with that), and how many batches are filled before the oldest is written.
  struct BatchShape {
    std::size_t moves = 0, points = 0, in_flight = 0;
  };
  /// On one thread a batch is written as soon as it is compensated, while its moves are
  /// still in the core's cache: a move's task is 1.2 kB and is touched three times (read,
  /// solved, written).
  static constexpr BatchShape kInline{256, 4 * 256, 1};
  /// With a worker, each batch handed over costs both threads a wake-up: batches of 1024
  /// moves (5 MB of tasks in the ring) against 256 cut two threads' time on the 1M-line
  /// finishing program by 10% (0.59 -> 0.53 s), where on one thread they cost 3%; 2,048
  /// were 2% faster again for twice the memory. Four batches: while one fills, the others
  /// may wait for or be in compensation, so that a batch the reading thread took longer
  /// over does not leave the worker idle.
  static constexpr BatchShape kThreaded{1024, 4 * 1024, 4};
  /// The ring: as many batches as either shape keeps in flight.
  static constexpr std::size_t kBatches = std::max(kInline.in_flight, kThreaded.in_flight);
  static_assert(kInline.in_flight >= 1 && kThreaded.in_flight >= 1);
  /// An arc of more chords is compensated and written in parts of this many: a helix of a
  /// thousand turns must not hold a million points.
  static constexpr std::size_t kPartChords = 8192;

  using Writer = std::function<void(MoveTask&)>;

  /// `write` takes each compensated move, in program order, on the caller's thread;
  /// `split` says who does the work either thread may (the reading thread or the worker).
  MovePipeline(MoveSolver& solver, bool worker_thread, WorkSplit split, Writer write);

  /// Whether the reading thread takes the nominal end poses of the moves it queues now (the
  /// worker takes those it leaves), as the split says. Adaptive: while the reading thread
  /// had to wait for the worker to write the last batch it came to, it has time to spare;
  /// else the worker has (it also takes the error before at the batch's probes). Which
  /// thread does it changes nothing written: the same pose, the same largest error.
  [[nodiscard]] bool reader_helps() const { return reader_helps_; }

  /// The next task to fill; queued() hands it on once filled.
  [[nodiscard]] MoveTask& next_task();
  /// The task next_task() gave is filled; it is expected to give about `points` points.
  void queued(std::size_t points);

  /// Compensates and writes every move queued so far.
  void drain();
  /// The job stopped with an error: a move queued before it may have failed first (its
  /// error is the one to report), unless the error came from writing the moves.
  void abandon();

 private:
  void pass_batch();
  void write_oldest();
  void write_batch(MoveBatch& batch);

  MoveSolver& solver_;
  WorkSplit split_;
  bool reader_helps_;
  Writer write_;
  BatchShape shape_;
  std::array<MoveBatch, kBatches> batches_;
  std::size_t filling_ = 0;       ///< the batch the interpreter fills
  std::size_t batch_points_ = 0;  ///< the points expected of the batch being filled
  struct InFlight {
    std::size_t batch = 0;   ///< index into batches_
    std::size_t ticket = 0;  ///< the worker's, for its compensation
  };
  std::deque<InFlight> in_flight_;  ///< filled batches in program order, to be written
  bool failed_ = false;             ///< writing a move failed: nothing more is written
  /// Last: destroyed (joined) first, while what it works on still exists.
  std::unique_ptr<util::BackgroundThread> worker_;
};

}  // namespace ccomp::compensate
