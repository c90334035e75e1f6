// open_backend: knobs, model, threads, reset.
#include "backends/open_backend.hpp"

namespace chainmail {

OpenedBackend open_backend(const Scene& scene, const Weave& weave, const BackendInfo& info,
                           int threads) {
  OpenedBackend opened;
  opened.knobs = resolve_knobs(scene, info);
  opened.model = info.create();
  opened.model->set_threads(threads);  // before reset (Backend::set_threads)
  opened.model->reset(scene, weave, opened.knobs);
  return opened;
}

}  // namespace chainmail
