// plausible model: see plausible.hpp
