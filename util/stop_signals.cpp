#include "util/stop_signals.h"

#include <csignal>

namespace anticrack
{
  namespace
  {
    volatile std::sig_atomic_t stop_requested = 0;
    extern "C" void request_stop(int) { stop_requested = 1; }
  } // namespace

  StopSignals::StopSignals()
  {
    stop_requested = 0;
    previous_int_ = std::signal(SIGINT, request_stop);
    previous_term_ = std::signal(SIGTERM, request_stop);
  }

  StopSignals::~StopSignals()
  {
    std::signal(SIGINT, previous_int_);
    std::signal(SIGTERM, previous_term_);
  }

  bool StopSignals::requested() { return stop_requested != 0; }
} // namespace anticrack
