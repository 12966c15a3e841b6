// Batching and the worker thread on their own: every move queued comes out once, in program
// order, compensated alike on one thread and two; a failure stops the writing where it is.
#include "compensate/move_pipeline.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "ccomp/compensate/machine_coordinates.hpp"
#include "job_runner.hpp"

namespace ccomp::compensate {
namespace {

class MovePipelineTest : public ::testing::TestWithParam<bool> {
 protected:
  MovePipelineTest() : forward_(test::sample_machine("hmc-xyzb-geometric")), scratch_(forward_) {
    offsets_.tool = {0, 0, 100.0};
  }

  /// Queues a feed along X from x to x + 1, as the job's reader fills a task.
  void queue(MovePipeline& pipeline, double x) {
    MoveTask& t = pipeline.next_task();
    t.first = first_;
    first_ = false;
    t.offsets = offsets_;
    t.motion.kind = gcode::MotionKind::feed;
    t.motion.start = {x, -40, -100, 0, 0, 0, 0, 0, 0};
    t.motion.end = {x + 1, -40, -100, 0, 0, 0, 0, 0, 0};
    t.motion.offsets = &t.offsets;
    model::forward(forward_, scratch_, compensate::chain_of(t.motion.end, t.offsets), {}, false, model::Evaluate::nominal);
    t.end_pose = {scratch_.nominal, scratch_.R_nominal};
    t.end_pose_known = true;
    pipeline.queued(1);
  }

  /// The written moves' start x and their last compensated points, for `moves` moves.
  struct Written {
    std::vector<double> x;
    std::vector<model::ChainQ> q;
  };
  Written run(bool worker, int moves) {
    first_ = true;
    MoveSolver solver(forward_, CompensationOptions{});
    Written w;
    MovePipeline pipeline(solver, worker, WorkSplit::adaptive, [&](MoveTask& t) {
      ASSERT_FALSE(t.error);
      w.x.push_back(t.motion.start[0]);
      w.q.push_back(t.points.back().q);
    });
    for (int k = 0; k < moves; ++k) queue(pipeline, -200.0 + 0.04 * k);
    pipeline.drain();
    return w;
  }

  model::ForwardModel forward_;
  model::ForwardData scratch_;
  gcode::Offsets offsets_;
  bool first_ = true;
};

TEST_P(MovePipelineTest, WritesEveryMoveOnceInProgramOrderAcrossBatches) {
  // Five batches on two threads, more than the ring holds (17 on one thread).
  const int moves = static_cast<int>(4 * MovePipeline::kThreaded.moves + 17);
  const Written w = run(GetParam(), moves);
  ASSERT_EQ(w.x.size(), static_cast<std::size_t>(moves));
  for (int k = 0; k < moves; ++k) ASSERT_DOUBLE_EQ(w.x[static_cast<std::size_t>(k)], -200.0 + 0.04 * k) << k;
}

TEST_P(MovePipelineTest, CompensatesAlikeOnOneThreadAndTwo) {
  const int moves = static_cast<int>(MovePipeline::kThreaded.moves + 300);  // two batches on two threads
  const Written here = run(false, moves), there = run(GetParam(), moves);
  ASSERT_EQ(here.q.size(), there.q.size());
  for (std::size_t k = 0; k < here.q.size(); ++k) ASSERT_EQ(here.q[k], there.q[k]) << k;
  EXPECT_GT((here.q[0].head<3>() - compensate::chain_of({-199.0, -40, -100}, offsets_).head<3>()).norm(), 1e-6)
      << "the moves were compensated";
}

TEST_P(MovePipelineTest, AFailedWriteStopsTheWritingAndAbandonWritesNothingMore) {
  MoveSolver solver(forward_, CompensationOptions{});
  std::size_t written = 0;
  MovePipeline pipeline(solver, GetParam(), WorkSplit::adaptive, [&](MoveTask&) {
    if (++written == 10) throw std::runtime_error("disk full");
  });
  for (int k = 0; k < 40; ++k) queue(pipeline, 0.5 * k);
  EXPECT_THROW(pipeline.drain(), std::runtime_error);
  pipeline.abandon();
  EXPECT_EQ(written, 10U);
}

INSTANTIATE_TEST_SUITE_P(Threads, MovePipelineTest, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& p) { return p.param ? "worker" : "inline"; });

}  // namespace
}  // namespace ccomp::compensate
