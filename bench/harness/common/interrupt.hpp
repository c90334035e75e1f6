// Ctrl-C and SIGTERM: the first one asks the running command to stop at the next step, write what
// has finished (verdict `interrupted` for the rest) and exit 130; a second one ends the process.
#pragma once

namespace chainmail {

void install_interrupt_handlers();
bool interrupted();
// for tests: as if a signal had arrived (true) or none (false)
void set_interrupted(bool value);

}  // namespace chainmail
