#include "reports/x_display.hpp"

#include <cstdlib>
#include <cstring>
#include <chrono>
#include <mutex>
#include <thread>

#include <X11/Xlib.h>

namespace orthosonar::reports::detail {
namespace {

std::mutex g_mutex;
Display* g_display = nullptr;  // never closed: see the header

}  // namespace

void* shared_x_display() {
  const char* name = std::getenv("DISPLAY");
  if (name == nullptr || std::strlen(name) == 0) return nullptr;
  std::lock_guard<std::mutex> lock(g_mutex);
  // A server that is resetting (its previous last client just left) refuses briefly: retry.
  for (int attempt = 0; g_display == nullptr && attempt < 20; ++attempt) {
    g_display = XOpenDisplay(name);
    if (g_display == nullptr) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return g_display;
}

std::string x_display_problem() {
  const char* name = std::getenv("DISPLAY");
  if (name == nullptr || std::strlen(name) == 0) return "DISPLAY is unset";
  if (shared_x_display() == nullptr) return std::string("cannot connect to X display '") + name + "'";
  return {};
}

}  // namespace orthosonar::reports::detail
