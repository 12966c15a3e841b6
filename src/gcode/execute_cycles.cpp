// What a canned cycle block does (G73, G81-G89 with G98/G99, G91 and L repeats), as
// rs274ngc's convert_cycle_* do.
#include <fmt/format.h>

#include <cmath>

#include "ccomp/constants.hpp"
#include "g_codes.hpp"
#include "interpreter_impl.hpp"

namespace ccomp::gcode {

void Interpreter::Impl::cycle_move(MotionKind kind, std::size_t first, std::size_t second, std::size_t normal, double a,
                                   double b, double c) {
  Axes t = position;
  t[first] = a + offsets.origin(first);
  t[second] = b + offsets.origin(second);
  t[normal] = c + offsets.origin(normal);
  straight(kind, t, MotionSource::canned_cycle);
}

void Interpreter::Impl::canned_cycle(const Block& b, int code) {
  const PlaneAxes pa = plane_axes(modal.plane);
  const double u = unit();
  for (std::size_t i = 3; i < kAxisCount; ++i)
    if (words.has(kAxisLetters[i]))
      fail(b, words.word[static_cast<std::size_t>(kAxisLetters[i] - 'A')],
           fmt::format("cannot put an {} in canned cycle", static_cast<char>(std::tolower(kAxisLetters[i]))));
  if (modal.cutter_compensation != 400)
    fail(b, nullptr, "cannot use a canned cycle with cutter radius compensation on");
  if (modal.feed == 0.0 && modal.feed_mode != FeedMode::inverse_time)
    fail(b, nullptr, "cannot feed with zero feed rate: a canned cycle feeds (no F word yet)");
  const char first_letter = kAxisLetters[pa.first], second_letter = kAxisLetters[pa.second];
  const char depth_letter = kAxisLetters[pa.normal];
  // R, the depth, P and Q are sticky while the cycle stays in force.
  if (words.has('R'))
    cycle_r = words['R'] * u;
  else if (!cycle_values_set)
    fail(b, nullptr, "R word missing with canned cycle");
  if (words.has(depth_letter))
    cycle_bottom = words[depth_letter] * u;
  else if (!cycle_values_set)
    fail(b, nullptr, fmt::format("{} word missing with canned cycle", depth_letter));
  if (words.has('P')) cycle_p = words['P'];
  if (words.has('Q')) cycle_q = words['Q'] * u;
  cycle_values_set = true;
  // A bound on the moves one cycle block makes: L repeats and pecks (a Q far smaller than
  // the depth, or too small to change it at all) would otherwise run for hours or for ever.
  constexpr int kMaxCycleMoves = 100'000;
  int repeats = 1;
  if (words.has('L')) {
    const double l = words['L'];
    if (l < 0 || l != std::floor(l))
      fail(b, words.word['L' - 'A'], "L word for canned cycle repeats must be a non-negative integer");
    if (l > kMaxCycleMoves)
      fail(b, words.word['L' - 'A'], fmt::format("L{} canned cycle repeats: more than {}", l, kMaxCycleMoves));
    repeats = static_cast<int>(l);
  }
  // The initial level is where the first of a run of cycle blocks started (rs274's
  // cycle_il): a G91 R counts from it, and G98 returns to it, however the blocks come.
  if (!cycle_initial_set) cycle_initial = program(pa.normal), cycle_initial_set = true;
  double old_cc = cycle_initial;
  double aa = program(pa.first), bb = program(pa.second);
  double aa_step = 0.0, bb_step = 0.0, r = 0.0, cc = 0.0;
  if (modal.absolute) {
    if (words.has(first_letter)) aa = words[first_letter] * u;
    if (words.has(second_letter)) bb = words[second_letter] * u;
    r = cycle_r;
    cc = cycle_bottom;
  } else {
    if (words.has(first_letter)) aa_step = words[first_letter] * u;
    if (words.has(second_letter)) bb_step = words[second_letter] * u;
    r = cycle_r + old_cc;
    cc = r + cycle_bottom;
  }
  if (r < cc) {
    const std::string what =
        fmt::format("R value ({}) less than {} value ({}) in canned cycle", r / u, depth_letter, cc / u);
    // LinuxCNC refuses this; Fanuc-family controls feed "down" to a bottom above R.
    if (!options.dialect.cycles_own_modal_group) fail(b, nullptr, what);
    warn(what + ": the hole's bottom is above the R plane", b.line);
  }
  if ((code == 730 || code == 830) && cycle_q <= 0.0)
    fail(b, nullptr, fmt::format("Q word missing or not positive with {}", g_name(code)));
  if ((code == 840 || code == 860 || code == 880) && modal.spindle == 0 && options.dialect.cycles_need_spindle)
    fail(b, nullptr, fmt::format("spindle not turning in {}", g_name(code)));
  position_unknown &= ~((1U << pa.first) | (1U << pa.second) | (1U << pa.normal));
  int moves = 0;
  auto count_move = [&] {
    if (++moves > kMaxCycleMoves)
      fail(b, nullptr,
           fmt::format("{} makes more than {} moves (L repeats, and pecks of Q {} down to {} {}): a runaway cycle",
                       g_name(code), kMaxCycleMoves, cycle_q / u, depth_letter, cc / u));
  };
  auto traverse = [&](double a, double bv, double c) {
    count_move();
    cycle_move(MotionKind::traverse, pa.first, pa.second, pa.normal, a, bv, c);
  };
  auto feed = [&](double a, double bv, double c) {
    count_move();
    cycle_move(MotionKind::feed, pa.first, pa.second, pa.normal, a, bv, c);
  };
  double current_cc = program(pa.normal);  // the level the tool is at
  if (old_cc < r) {
    traverse(program(pa.first), program(pa.second), r);
    old_cc = current_cc = r;
  }
  const double clear = modal.retract_to_r ? r : old_cc;
  const double rapid_delta = 0.010 * kMmPerInch;  // rs274ngc: 0.010 inch, in mm
  for (int rep = 0; rep < repeats; ++rep) {
    aa += aa_step;
    bb += bb_step;
    // rs274: the first hole is reached at the level the tool is at (when above R), every
    // other at the clearance level; then down to R.
    if (rep == 0 && current_cc > r) {
      traverse(aa, bb, current_cc);
      traverse(aa, bb, r);
    } else {
      traverse(aa, bb, clear);
      if (clear > r) traverse(aa, bb, r);
    }
    switch (code) {
      case 810:
        feed(aa, bb, cc);
        traverse(aa, bb, clear);
        break;
      case 820:
        feed(aa, bb, cc);
        emit("DWELL", fixed4(cycle_p));
        traverse(aa, bb, clear);
        break;
      case 730:
      case 830:
        for (double depth = r - cycle_q; depth > cc; depth -= cycle_q) {
          feed(aa, bb, depth);
          if (code == 830) traverse(aa, bb, r);
          traverse(aa, bb, depth + rapid_delta);
        }
        feed(aa, bb, cc);
        traverse(aa, bb, clear);
        break;
      case 840:
        feed(aa, bb, cc);
        emit("DWELL", fixed4(0));
        feed(aa, bb, clear);
        break;
      case 850:
        feed(aa, bb, cc);
        feed(aa, bb, r);
        traverse(aa, bb, clear);
        break;
      case 860:
        feed(aa, bb, cc);
        emit("DWELL", fixed4(cycle_p));
        emit("STOP_SPINDLE_TURNING", "0");
        traverse(aa, bb, clear);
        emit("START_SPINDLE_CLOCKWISE", "0");
        break;
      case 880: {
        feed(aa, bb, cc);
        emit("DWELL", fixed4(cycle_p));
        emit("STOP_SPINDLE_TURNING", "0");
        emit("PROGRAM_STOP", "");
        // The operator retracts by hand: the program resumes at the clearance level.
        position[pa.normal] = clear + offsets.origin(pa.normal);
        warn("G88: the operator retracts by hand; ccomp continues from the clearance level", b.line);
        break;
      }
      case 890:
        feed(aa, bb, cc);
        emit("DWELL", fixed4(cycle_p));
        feed(aa, bb, clear);
        break;
      default:
        break;
    }
  }
}

}  // namespace ccomp::gcode
