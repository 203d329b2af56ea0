//! The one embedded font: DejaVu Sans, registered with plotters under the
//! family `sans-serif` for every text the crate draws (report plots and
//! CT previews), so that no system font library is needed.
//!
//! A leaf of the crate: it imports nothing of it.

use std::sync::OnceLock;

use plotters::style::FontStyle;

/// DejaVu Sans 2.37 from Debian's fonts-dejavu-core 2.37-6 (Bitstream Vera
/// licence; see `assets/fonts/LICENSE` and `assets/fonts/PROVENANCE`).
static DEJAVU_SANS: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");

/// The font family every drawn text uses; SVG files name it as is.
pub const FAMILY: &str = "sans-serif";

/// The embedded font could not be registered with plotters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the embedded DejaVu Sans font could not be loaded")]
pub struct FontError;

/// Registers the embedded font with plotters, once per process.
pub fn ensure_font() -> Result<(), FontError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FAMILY, FontStyle::Normal, DEJAVU_SANS).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(FontError)
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_embedded_font_registers() {
        assert_eq!(super::ensure_font(), Ok(()));
    }
}
