#include "move_pipeline.hpp"

#include <utility>

namespace ccomp::compensate {

MovePipeline::MovePipeline(MoveSolver& solver, bool worker_thread, WorkSplit split, Writer write)
    : solver_(solver),
      split_(split),
      reader_helps_(split != WorkSplit::worker),
      write_(std::move(write)),
      shape_(worker_thread ? kThreaded : kInline) {
  if (worker_thread) worker_ = std::make_unique<util::BackgroundThread>();
}

MoveTask& MovePipeline::next_task() {
  MoveBatch& batch = batches_[filling_];
  if (batch.tasks.empty()) batch.tasks.resize(shape_.moves);
  return batch.tasks[batch.filled++];
}

void MovePipeline::queued(std::size_t points) {
  batch_points_ += points;
  const MoveBatch& batch = batches_[filling_];
  if (batch.filled == shape_.moves || batch_points_ >= shape_.points) pass_batch();
}

/// The filled batch goes to be compensated; when no batch is left to fill, the oldest is
/// written once compensated, and filled next.
void MovePipeline::pass_batch() {
  const std::size_t b = filling_;
  batch_points_ = 0;
  batches_[b].probes_on_worker = !reader_helps_;
  if (split_ == WorkSplit::alternate) reader_helps_ = !reader_helps_;
  std::size_t ticket = 0;
  if (worker_)
    ticket = worker_->run([this, b] { solver_.solve_batch(batches_[b]); });
  else
    solver_.solve_batch(batches_[b]);
  in_flight_.push_back({b, ticket});
  filling_ = (filling_ + 1) % shape_.in_flight;  // the ring's order: the oldest batch is next
  if (in_flight_.size() == shape_.in_flight) write_oldest();
}

void MovePipeline::write_oldest() {
  const InFlight oldest = in_flight_.front();
  // (Without a worker thread the batch was solved in line: the reading thread does all.)
  if (split_ == WorkSplit::adaptive) reader_helps_ = !worker_ || !worker_->done(oldest.ticket);
  if (worker_) worker_->wait(oldest.ticket);
  in_flight_.pop_front();
  write_batch(batches_[oldest.batch]);
}

void MovePipeline::drain() {
  if (batches_[filling_].filled > 0) pass_batch();
  while (!in_flight_.empty()) write_oldest();
}

void MovePipeline::abandon() {
  if (worker_) worker_->wait();
  if (!failed_) drain();
}

void MovePipeline::write_batch(MoveBatch& batch) {
  try {
    for (std::size_t k = 0; k < batch.filled; ++k) {
      MoveTask& t = batch.tasks[k];
      write_(t);
      // A slot keeps its storage for the next move, but not what an unusual move needed (a
      // split, a long line): else over a long program every slot would come to hold the
      // most any of its moves needed.
      if (t.points.capacity() > 2) std::vector<CompensatedPoint>().swap(t.points);
      if (t.probes.capacity() > 2) std::vector<ErrorProbe>().swap(t.probes);
      if (t.block.words.capacity() > 8) std::vector<gcode::Word>().swap(t.block.words);
      if (t.text.capacity() > 64) std::string().swap(t.text);
    }
  } catch (...) {
    failed_ = true;
    throw;
  }
  batch.filled = 0;
}

}  // namespace ccomp::compensate
