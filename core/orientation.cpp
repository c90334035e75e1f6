#include "core/orientation.hpp"
