//! Which template a wall was fitted to: the names of the `template_source`
//! columns (the slice-wise mirror, the continuation, an explicit file, the
//! 3D mirror and the rim fill). Its own file, below the wall input and the
//! templates that name it.

/// Which template a wall was actually fitted to (the `template_source`
/// columns of `metrics.csv`, `validation.csv` and `validation_3d.csv`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum TemplateSource {
    /// The mirrored outer envelope `R(θ) = reflect(E(2α − θ))`.
    Mirror,
    /// The curvature-continuous continuation of both sides
    /// (`continuation_template`; beyond the thesis).
    Continuation,
    /// An explicit template file (`[defect] template`).
    File,
    /// The outer table mirrored across the 3D mid-sagittal plane
    /// ([`super::surface_template`]; beyond the thesis).
    Mirror3d,
    /// The rim fill: a sphere and a thin-plate spline through the bone
    /// around the defect ([`super::rim_fill`]; beyond the thesis).
    Rim,
}

impl TemplateSource {
    /// Every source, in the order of the tables' counts.
    pub const ALL: [TemplateSource; 5] = [
        TemplateSource::Mirror,
        TemplateSource::Continuation,
        TemplateSource::File,
        TemplateSource::Mirror3d,
        TemplateSource::Rim,
    ];

    /// The name in tables: `mirror`, `continuation`, `file`, `mirror3d`,
    /// `rim`.
    pub fn name(self) -> &'static str {
        match self {
            TemplateSource::Mirror => "mirror",
            TemplateSource::Continuation => "continuation",
            TemplateSource::File => "file",
            TemplateSource::Mirror3d => "mirror3d",
            TemplateSource::Rim => "rim",
        }
    }
}
