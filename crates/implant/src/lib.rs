//! metabezier-implant: the cranial implant of thesis ch. 6. CT volumes,
//! bone masks, contours, meshes and previews ([`ct`]); the mirror
//! technique, the fitted outer wall, the offset inner wall, the 3D implant
//! (STL) and its validation against the bone ([`implant`]).
//!
//! | # | room | what lives there |
//! |---|---|---|
//! | 10 | [`ct`] | CT volumes, bone masks, contours, meshes, previews |
//! | 13 | [`implant`] | the chapter-6 implant pipeline and its run (its report draws with `metabezier-plot`) |
//!
//! It stands on `metabezier-core`, `-files`, `-fit`, `-spec` (the implant
//! spec's grammar) and `-plot`, never on the campaign machinery or the
//! report; the rooms it uses are named at this root.
#![warn(missing_docs)]

use metabezier_core::{geometry, linalg, stats};
use metabezier_files as files;
use metabezier_fit::{fit, reconstruction};
use metabezier_plot::{font, markdown};

pub mod ct;

pub mod implant;
