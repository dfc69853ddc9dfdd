#include "host/app/energy_watch.h"

#include <cmath>
#include <cstdio>

namespace pd {

EnergyLog::EnergyLog(std::string path)
    : log_(std::move(path), "frame,step,time,kinetic,strain,contact,gravity,work,released,balance\n") {}

void EnergyLog::add(int64_t frame, int64_t step, double time, const Energy& e) {
  char line[320];
  std::snprintf(line, sizeof line, "%lld,%lld,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", (long long)frame,
                (long long)step, time, e.kinetic, e.strain, e.contact, e.gravity, e.work, e.released,
                e.balance());
  log_.add(line);
}

double energy_excess(const Energy& e0, const Energy& e) {
  // The scale is the energy the run started with plus what legitimately entered or left since
  // (external work, released bond energy, gravity's change), never the current kinetic or strain
  // energy: a blow-up grows those, and a scale containing them would hide it.
  const double in_play = std::fabs(e0.kinetic) + std::fabs(e0.strain) + std::fabs(e0.contact) +
                         std::fabs(e.work) + std::fabs(e.released) + std::fabs(e.gravity - e0.gravity);
  const double growth = e.balance() - e0.balance();
  if (in_play > 0) return growth / in_play;
  return growth > 0 ? INFINITY : 0;
}

int64_t fastest_particle(Engine& engine) {
  ParticleState s;
  engine.read_state(s);
  int64_t best = 0;
  double speed = -1;
  for (size_t i = 0; i < s.vel.size(); ++i)
    if (double(length(s.vel[i])) > speed) speed = length(s.vel[best = int64_t(i)]);
  return best;
}

}  // namespace pd
