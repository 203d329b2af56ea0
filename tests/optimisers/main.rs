//! The optimisers: every built-in on its problems, the registry of optimisers
//! and problems, COCO's bbob values, pycma parity, the overhead bench's checks
//! and the property tests.

mod bbob;
mod cmaes_parity;
mod optimisers_tests;
mod overhead;
mod registry;
