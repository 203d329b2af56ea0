//! The seeded fuzz loops of every reader (CT, outlines, results, specs), under
//! one counting allocator that refuses requests above an armed ceiling
//! (`fuzz_common`); `make fuzz` runs them longer.

#[path = "../common/mod.rs"]
mod common;
#[path = "../ct_inputs/mod.rs"]
mod ct_inputs;
#[path = "../fuzz_common/mod.rs"]
mod fuzz_common;

#[global_allocator]
static ALLOC: fuzz_common::CountingAlloc = fuzz_common::CountingAlloc;

mod fuzz_ct;
mod fuzz_outline;
mod fuzz_results;
mod fuzz_spec;
