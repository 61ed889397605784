//! Density expressions in x and y (`--density`), e.g. `1 + 10*exp(-((x-0.5)^2+y^2)/0.01)`.
