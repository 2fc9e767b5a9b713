#pragma once
// SIGINT/SIGTERM during long work: the first signal asks the command to stop
// at the next safe point (between solver iterations), where it throws
// Interrupted; nothing half-written is left, because every output is written
// to a temporary name and renamed (io/atomic_file.hpp). A second signal
// kills at once (the default action is restored).

#include <csignal>
#include <stdexcept>

namespace lhr::app {

// Exit code of an interrupted command: 128 + SIGINT, as shells report it.
constexpr int kExitInterrupted = 130;

struct Interrupted : std::runtime_error {
  Interrupted() : std::runtime_error("interrupted; no output was written") {}
};

inline volatile std::sig_atomic_t g_interrupt_signal = 0;

extern "C" inline void lhr_note_interrupt(int signal) {
  g_interrupt_signal = signal;
  std::signal(signal, SIG_DFL);
}

// A signal the parent ignored (a background job's SIGINT) stays ignored.
inline void install_interrupt_handlers() {
  for (const int signal : {SIGINT, SIGTERM}) {
    if (std::signal(signal, lhr_note_interrupt) == SIG_IGN) std::signal(signal, SIG_IGN);
  }
}

inline void throw_if_interrupted() {
  if (g_interrupt_signal != 0) throw Interrupted();
}

}  // namespace lhr::app
