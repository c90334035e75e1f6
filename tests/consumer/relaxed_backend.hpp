// A backend from outside chainmail: the paper's plausible model from chainmail::core, with more
// constraint sweeps, less drag and no shock propagation by default, and three knobs of its own.
#pragma once

namespace consumer {

// adds the backend "relaxed" to chainmail's registry (once, before anything reads it)
void register_relaxed_backend();

}  // namespace consumer
