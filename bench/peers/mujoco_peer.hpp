// What the MuJoCo peer programs share: a model from MJCF text (through MuJoCo's virtual file
// system, so nothing is written to disk) and mj_forward timed as `kanesens bench rhs` times
// its right-hand side.
#pragma once
#include <mujoco/mujoco.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include "batch_timing.hpp"

namespace mujoco_peer {

// nullptr, with MuJoCo's message on stderr, if the text does not load; `file` is its name there.
inline mjModel* load_mjcf(const std::string& xml, const char* file) {
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  if (mj_makeEmptyFileVFS(vfs.get(), file, static_cast<int>(xml.size())) != 0) return nullptr;
  std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), file)], xml.data(), xml.size());
  char error[1000] = "";
  mjModel* m = mj_loadXML(file, vfs.get(), error, sizeof error);
  mj_deleteVFS(vfs.get());
  if (!m) std::fprintf(stderr, "mj_loadXML: %s\n", error);
  return m;
}

// mj_forward at d's state; the last qacc of every call is added to `sink` (printed by the
// caller) so that no call can be optimised away.
inline peers::BatchTiming time_forward(const mjModel* m, mjData* d, int repeat, double batch_seconds, double& sink) {
  return peers::time_batches(
      [&] {
        mj_forward(m, d);
        sink += d->qacc[m->nv - 1];
      },
      repeat, batch_seconds);
}

}  // namespace mujoco_peer
