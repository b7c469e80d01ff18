// SPDX-License-Identifier: GPL-2.0-or-later
/* Jacking controller of the pile (docs/model.md §4.5): the phase state
   machine of fix jack/pile. Pure functions of the controller state, the tip
   depth and the head force; no LIGGGHTS dependency; unit-tested in
   tests/unit/test_jack_kernel.cpp.

   Conventions
   - depth: tip depth below the reference (positive downward), metres.
   - velocity: vertical pile velocity commanded for the next step, m/s,
     positive upward (push = negative).
   - head force: axial force of the grains on the pile, positive upward
     (resisting the push) = the compressive load the jack applies.

   Phases: PUSH (move down at v_push; the last step of a stroke is shortened
   so that the stroke ends exactly at its end depth), UNLOAD (move up at
   v_unload until head force <= zero_tol), PAUSE (`pause` seconds: stand
   still, or with pause_servo G > 0 hold the head force at zero by moving at
   v = G * head force, at most v_unload either way), DONE (target depth
   reached, stand still). Monotonic mode is one
   PUSH to the target depth, then DONE. Cyclic mode repeats
   PUSH -> UNLOAD -> PAUSE; the push that reaches the target depth ends in
   DONE (no unload after it). */

#ifndef CRUSH_JACK_KERNEL_H
#define CRUSH_JACK_KERNEL_H

#include <cmath>

namespace CrushKernels {

enum JackMode { JACK_MONOTONIC = 0, JACK_CYCLIC = 1 };
enum JackPhase { JACK_PUSH = 0, JACK_UNLOAD = 1, JACK_PAUSE = 2, JACK_DONE = 3 };
// Where a cyclic stroke ends: ABSOLUTE at depths S, 2S, 3S, ... below the
// reference (the rebound of each unload is pushed back in the next stroke);
// RELATIVE S below the depth at which the push began.
enum JackStrokes { JACK_STROKES_ABSOLUTE = 0, JACK_STROKES_RELATIVE = 1 };

struct JackParams {
  int mode;         // JackMode
  double v_push;    // push speed, > 0 (m/s)
  double depth;     // target depth, > 0 (m)
  // cyclic only
  double stroke;    // stroke length, > 0 (m)
  double v_unload;  // unloading speed, > 0 (m/s)
  double pause;     // duration of the zero-load pause, >= 0 (s)
  double zero_tol;  // unloading stops when head force <= zero_tol, >= 0 (N)
  int strokes;      // JackStrokes
  double pause_servo;  // >= 0 (m/s per N): 0 holds the position during the
                       // pause, > 0 holds the head force at zero
  double round_off;    // >= 0 (m): round-off of the measured depth (positions
                       // of mesh nodes moved step by step), part of the tolerance
};

struct JackState {
  int phase;          // JackPhase
  int cycle;          // 1-based number of the current stroke (push-unload-pause)
  int stroke_index;   // ABSOLUTE: the current stroke ends at stroke_index * stroke
  double stroke_end;  // depth at which the current push ends (<= target depth)
  double phase_time;  // time spent in the current phase (s)
};

inline JackParams jack_default_params()
{
  JackParams p;
  p.mode = JACK_MONOTONIC;
  p.v_push = -1.0;
  p.depth = -1.0;
  p.stroke = -1.0;
  p.v_unload = -1.0;
  p.pause = -1.0;
  p.zero_tol = 0.0;
  p.strokes = JACK_STROKES_ABSOLUTE;
  p.pause_servo = 0.0;
  p.round_off = 0.0;
  return p;
}

// Name of the first parameter out of its range ("v", "depth", "stroke",
// "v_unload", "pause", "zero_tol", "mode", "strokes", "pause_servo"), or 0
// when all are valid.
// Written so that NaN fails every test.
inline const char *jack_invalid_param(const JackParams &p)
{
  if (p.mode != JACK_MONOTONIC && p.mode != JACK_CYCLIC) return "mode";
  if (!(p.v_push > 0.0) || !std::isfinite(p.v_push)) return "v";
  if (!(p.depth > 0.0) || !std::isfinite(p.depth)) return "depth";
  if (p.mode == JACK_CYCLIC) {
    if (!(p.stroke > 0.0) || !std::isfinite(p.stroke)) return "stroke";
    if (!(p.v_unload > 0.0) || !std::isfinite(p.v_unload)) return "v_unload";
    if (!(p.pause >= 0.0) || !std::isfinite(p.pause)) return "pause";
    if (!(p.zero_tol >= 0.0) || !std::isfinite(p.zero_tol)) return "zero_tol";
    if (p.strokes != JACK_STROKES_ABSOLUTE && p.strokes != JACK_STROKES_RELATIVE) return "strokes";
    if (!(p.pause_servo >= 0.0) || !std::isfinite(p.pause_servo)) return "pause_servo";
  }
  return 0;
}

// A push has reached its end depth when it is less than this short of it:
// a billionth of one push step plus the round-off of the measured depth;
// far below a step. (Without the round-off term a tip far from z = 0 could
// be commanded steps smaller than the spacing of doubles, and never arrive.)
inline double jack_depth_tolerance(const JackParams &p, double dt)
{
  return 1e-9 * p.v_push * dt + p.round_off;
}

// End depth of the stroke that starts at `depth_start` as the stroke number
// `index` (ABSOLUTE) of the cyclic mode, capped at the target depth.
inline double jack_stroke_end(const JackParams &p, int index, double depth_start)
{
  if (p.mode != JACK_CYCLIC) return p.depth;
  const double end = (p.strokes == JACK_STROKES_ABSOLUTE) ? index * p.stroke
                                                          : depth_start + p.stroke;
  return end < p.depth ? end : p.depth;
}

// Commanded velocity for the next step in the current phase (no transition).
// PUSH moves down at v_push, or by exactly the remaining distance to the
// stroke end when that is less than one step: depth lands on the end.
// PAUSE with a servo moves up while the grains push the pile up (head force
// > 0) and down while they pull it down, v = pause_servo * head force,
// limited to v_unload.
inline double jack_velocity(const JackParams &p, const JackState &s, double depth,
                            double head_force, double dt)
{
  switch (s.phase) {
    case JACK_PUSH: {
      const double remaining = s.stroke_end - depth;
      if (!(remaining > 0.0)) return 0.0;
      return (remaining < p.v_push * dt) ? -remaining / dt : -p.v_push;
    }
    case JACK_UNLOAD:
      return p.v_unload;
    case JACK_PAUSE: {
      if (!(p.pause_servo > 0.0)) return 0.0;
      const double v = p.pause_servo * head_force;
      if (v > p.v_unload) return p.v_unload;
      if (v < -p.v_unload) return -p.v_unload;
      return v;
    }
    default:
      return 0.0;
  }
}

// Phase transitions at the current depth and head force; cascades (an unload
// that starts at zero head load goes straight to the pause, a zero pause
// straight to the next push). Returns true when the phase changed.
inline bool jack_transitions(const JackParams &p, JackState &s, double depth, double head_force,
                             double dt)
{
  const double tol_depth = jack_depth_tolerance(p, dt);
  // pause time is a sum of steps: allow a millionth of a step of round-off
  const double tol_time = 1e-6 * dt;
  bool changed = false;
  for (int guard = 0; guard < 8; guard++) {
    const int before = s.phase;
    if (s.phase == JACK_PUSH) {
      if (depth >= s.stroke_end - tol_depth) {
        if (p.mode != JACK_CYCLIC || s.stroke_end >= p.depth - tol_depth) s.phase = JACK_DONE;
        else s.phase = JACK_UNLOAD;
      }
    } else if (s.phase == JACK_UNLOAD) {
      if (head_force <= p.zero_tol) s.phase = JACK_PAUSE;
    } else if (s.phase == JACK_PAUSE) {
      if (s.phase_time >= p.pause - tol_time) {
        s.phase = JACK_PUSH;
        s.cycle++;
        s.stroke_index++;
        s.stroke_end = jack_stroke_end(p, s.stroke_index, depth);
      }
    }
    if (s.phase == before) break;
    s.phase_time = 0.0;
    changed = true;
  }
  return changed;
}

// Initial state for a tip at depth0: PUSH of stroke 1, whose end is the first
// multiple of the stroke below depth0 (ABSOLUTE; at least one stroke), or
// depth0 + stroke (RELATIVE), or the target (monotonic); DONE when depth0 is
// already at the target. Returns the velocity of the first step.
inline double jack_start(const JackParams &p, JackState &s, double depth0, double dt)
{
  s.phase = JACK_PUSH;
  s.cycle = 1;
  s.phase_time = 0.0;
  s.stroke_index = 1;
  if (p.mode == JACK_CYCLIC && p.strokes == JACK_STROKES_ABSOLUTE) {
    const double k = std::floor(depth0 / p.stroke + 1e-9) + 1.0;
    s.stroke_index = (k > 1.0) ? (int)k : 1;
  }
  s.stroke_end = jack_stroke_end(p, s.stroke_index, depth0);
  if (depth0 >= p.depth - jack_depth_tolerance(p, dt)) s.phase = JACK_DONE;
  return jack_velocity(p, s, depth0, 0.0, dt);
}

// One controller update at the end of a step of length dt_done: the phase
// clock advances, the phase changes if due, and the velocity for the next
// step (length dt_next) is returned.
inline double jack_update(const JackParams &p, JackState &s, double depth, double head_force,
                          double dt_done, double dt_next, bool *changed = 0)
{
  s.phase_time += dt_done;
  const bool c = jack_transitions(p, s, depth, head_force, dt_next);
  if (changed) *changed = c;
  return jack_velocity(p, s, depth, head_force, dt_next);
}

// Axial force on the whole pile from the force measured in a chamber sector
// of sector_deg degrees (0 < sector_deg <= 360) bounded by symmetry planes
// through the pile axis: the grains of the sector touch that fraction of the
// pile's surface, and by symmetry the other sectors carry the same force.
inline double jack_full_pile_force(double f_sector, double sector_deg)
{
  return f_sector * (360.0 / sector_deg);
}

}  // namespace CrushKernels

#endif
