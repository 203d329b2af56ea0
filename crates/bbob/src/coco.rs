//! COCO's C core behind a safe handle: problems, evaluations and the
//! observer that writes COCO's logs (compiled with the `coco` feature).

use std::ffi::{c_char, c_double, c_int, CStr, CString};
use std::sync::{Mutex, Once};

use metabezier_core::problem::{Bounds, Problem};

use crate::{BbobError, BBOB_DIMENSIONS};

#[repr(C)]
struct RawBbob {
    _private: [u8; 0],
}

#[repr(C)]
struct RawObserver {
    _private: [u8; 0],
}

extern "C" {
    fn mb_coco_quiet();
    fn mb_observer_new(
        outer_folder: *const c_char,
        result_folder: *const c_char,
        algorithm: *const c_char,
    ) -> *mut RawObserver;
    fn mb_observer_folder(observer: *const RawObserver) -> *const c_char;
    fn mb_observer_free(observer: *mut RawObserver);
    fn mb_bbob_new(
        function: usize,
        dimension: usize,
        instance: usize,
        observer: *mut RawObserver,
    ) -> *mut RawBbob;
    fn mb_bbob_evaluate(b: *mut RawBbob, x: *const c_double, y: *mut c_double);
    fn mb_bbob_fopt(b: *const RawBbob) -> c_double;
    fn mb_bbob_final_target_delta(b: *const RawBbob) -> c_double;
    fn mb_bbob_evaluations(b: *const RawBbob) -> usize;
    fn mb_bbob_final_target_hit(b: *const RawBbob) -> c_int;
    fn mb_bbob_id(b: *const RawBbob) -> *const c_char;
    fn mb_bbob_lower(b: *const RawBbob) -> c_double;
    fn mb_bbob_upper(b: *const RawBbob) -> c_double;
    fn mb_bbob_free(b: *mut RawBbob);
}

/// COCO's suite and problem constructors touch process-wide state (log
/// level, observers' open files): they run one at a time.
static COCO: Mutex<()> = Mutex::new(());

/// Takes the COCO lock, silencing COCO's informational output once.
fn lock_coco() -> std::sync::MutexGuard<'static, ()> {
    static QUIET: Once = Once::new();
    let guard = COCO.lock().unwrap_or_else(|p| p.into_inner());
    // SAFETY: sets COCO's log level; called under the lock.
    QUIET.call_once(|| unsafe { mb_coco_quiet() });
    guard
}

/// COCO's `bbob` observer: problems made with [`BbobProblem::observed`]
/// log the `.info`, `.dat` and `.tdat` files that COCO's post-processing
/// (`cocopp`) reads, into one folder per algorithm.
pub struct CocoObserver {
    raw: *mut RawObserver,
    folder: String,
}

impl CocoObserver {
    /// An observer writing into `outer/result` (COCO appends `-001`, … when
    /// that folder exists) under `algorithm`. `outer` must exist and be
    /// writable: COCO ends the process when it cannot create its folder, so
    /// the caller checks that first.
    pub fn new(outer: &str, result: &str, algorithm: &str) -> Result<Self, BbobError> {
        let c = |s: &str| -> Result<CString, BbobError> {
            if s.is_empty() || s.len() > 1000 || s.chars().any(char::is_whitespace) {
                return Err(BbobError::Name(s.to_owned()));
            }
            CString::new(s).map_err(|_| BbobError::Name(s.to_owned()))
        };
        let (o, r, a) = (c(outer)?, c(result)?, c(algorithm)?);
        let _guard = lock_coco();
        // SAFETY: valid C strings; the observer is freed in Drop.
        unsafe {
            let raw = mb_observer_new(o.as_ptr(), r.as_ptr(), a.as_ptr());
            if raw.is_null() {
                return Err(BbobError::Name(outer.to_owned()));
            }
            let folder = CStr::from_ptr(mb_observer_folder(raw))
                .to_string_lossy()
                .into_owned();
            Ok(CocoObserver { raw, folder })
        }
    }

    /// The folder COCO writes into.
    pub fn folder(&self) -> &str {
        &self.folder
    }
}

impl Drop for CocoObserver {
    fn drop(&mut self) {
        let _guard = lock_coco();
        // SAFETY: made by mb_observer_new, freed once, after its problems.
        unsafe { mb_observer_free(self.raw) };
    }
}

/// One bbob problem: function `f` (1..=24) at dimension `D`, instance `k`,
/// evaluated by COCO. Owns its COCO handle; not shared between threads.
pub struct BbobProblem {
    raw: *mut RawBbob,
    function: usize,
    instance: usize,
    bounds: Vec<Bounds>,
    id: String,
    fopt: f64,
    final_target: f64,
}

// The handle is used by one thread at a time (it is moved into a run, never
// shared), and COCO's evaluation touches only the problem's own data.
unsafe impl Send for BbobProblem {}

impl BbobProblem {
    /// Checks that COCO defines function `function` at `dimension`, instance
    /// `instance`, before any call into COCO (which would end the process).
    pub fn check(function: usize, dimension: usize, instance: usize) -> Result<(), BbobError> {
        if !(1..=24).contains(&function) {
            return Err(BbobError::Function(function));
        }
        if !BBOB_DIMENSIONS.contains(&dimension) {
            return Err(BbobError::Dimension(dimension));
        }
        if !(1..=1_000_000).contains(&instance) {
            return Err(BbobError::Instance(instance));
        }
        Ok(())
    }

    /// Function `function` at `dimension`, instance `instance`.
    pub fn new(function: usize, dimension: usize, instance: usize) -> Result<Self, BbobError> {
        Self::make(function, dimension, instance, std::ptr::null_mut())
    }

    /// The same, observed by COCO's `bbob` logger ([`CocoObserver`]),
    /// which must outlive it.
    pub fn observed(
        function: usize,
        dimension: usize,
        instance: usize,
        observer: &CocoObserver,
    ) -> Result<Observed<'_>, BbobError> {
        Ok(Observed {
            problem: Self::make(function, dimension, instance, observer.raw)?,
            _observer: std::marker::PhantomData,
        })
    }

    fn make(
        function: usize,
        dimension: usize,
        instance: usize,
        observer: *mut RawObserver,
    ) -> Result<Self, BbobError> {
        Self::check(function, dimension, instance)?;
        let _guard = lock_coco();
        // SAFETY: the arguments were checked above; COCO owns the returned
        // handle until mb_bbob_free.
        unsafe {
            let raw = mb_bbob_new(function, dimension, instance, observer);
            if raw.is_null() {
                return Err(BbobError::Refused {
                    function,
                    dimension,
                    instance,
                });
            }
            let (lower, upper) = (mb_bbob_lower(raw), mb_bbob_upper(raw));
            Ok(BbobProblem {
                raw,
                function,
                instance,
                bounds: vec![Bounds::new(lower, upper); dimension],
                id: CStr::from_ptr(mb_bbob_id(raw))
                    .to_string_lossy()
                    .into_owned(),
                fopt: mb_bbob_fopt(raw),
                final_target: mb_bbob_final_target_delta(raw),
            })
        }
    }

    /// COCO's problem id, such as `bbob_f008_i02_d05`.
    pub fn id(&self) -> &str {
        &self.id
    }

    /// The function index 1..=24.
    pub fn function(&self) -> usize {
        self.function
    }

    /// The instance number.
    pub fn instance(&self) -> usize {
        self.instance
    }

    /// The optimal value `f*` of this instance.
    pub fn fopt(&self) -> f64 {
        self.fopt
    }

    /// COCO's final target precision `Δf` (10⁻⁸).
    pub fn final_target_delta(&self) -> f64 {
        self.final_target
    }

    /// Evaluations COCO counted.
    pub fn coco_evaluations(&self) -> u64 {
        // SAFETY: the handle is live.
        unsafe { mb_bbob_evaluations(self.raw) as u64 }
    }

    /// Whether COCO saw the final target `f* + Δf` hit.
    pub fn final_target_hit(&self) -> bool {
        // SAFETY: the handle is live.
        unsafe { mb_bbob_final_target_hit(self.raw) != 0 }
    }
}

impl Problem for BbobProblem {
    fn dim(&self) -> usize {
        self.bounds.len()
    }

    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    fn objective(&self, x: &[f64]) -> f64 {
        assert_eq!(
            x.len(),
            self.bounds.len(),
            "{}: wrong number of variables",
            self.id
        );
        let mut y = 0.0;
        // SAFETY: x has the problem's dimension; the handle is live and used
        // by this thread only (BbobProblem is Send, not Sync).
        unsafe { mb_bbob_evaluate(self.raw, x.as_ptr(), &mut y) };
        y
    }
}

/// A [`BbobProblem`] logged by an observer it may not outlive.
pub struct Observed<'o> {
    problem: BbobProblem,
    _observer: std::marker::PhantomData<&'o CocoObserver>,
}

impl std::ops::Deref for Observed<'_> {
    type Target = BbobProblem;
    fn deref(&self) -> &BbobProblem {
        &self.problem
    }
}

impl Problem for Observed<'_> {
    fn dim(&self) -> usize {
        self.problem.dim()
    }

    fn bounds(&self) -> &[Bounds] {
        self.problem.bounds()
    }

    fn objective(&self, x: &[f64]) -> f64 {
        self.problem.objective(x)
    }
}

impl Drop for BbobProblem {
    fn drop(&mut self) {
        let _guard = lock_coco();
        // SAFETY: the handle was made by mb_bbob_new and is freed once.
        unsafe { mb_bbob_free(self.raw) };
    }
}

impl std::fmt::Debug for BbobProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BbobProblem")
            .field("id", &self.id)
            .field("fopt", &self.fopt)
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{bbob_function, bbob_group};

    #[test]
    fn names_and_indices() {
        assert_eq!(bbob_function("f8"), Some(8));
        assert_eq!(bbob_function("15"), Some(15));
        assert_eq!(bbob_function("rosenbrock"), Some(8));
        assert_eq!(bbob_function("f25"), None);
        assert_eq!(bbob_function("ackley"), None);
        assert_eq!(bbob_group(17), "multimodal, adequate structure");
    }

    #[test]
    fn bad_arguments_never_reach_coco() {
        assert_eq!(
            BbobProblem::new(0, 2, 1).unwrap_err(),
            BbobError::Function(0)
        );
        assert_eq!(
            BbobProblem::new(25, 2, 1).unwrap_err(),
            BbobError::Function(25)
        );
        assert_eq!(
            BbobProblem::new(1, 4, 1).unwrap_err(),
            BbobError::Dimension(4)
        );
        assert_eq!(
            BbobProblem::new(1, 2, 0).unwrap_err(),
            BbobError::Instance(0)
        );
    }

    #[test]
    fn coco_counts_our_evaluations_and_the_optimum_hits_the_final_target() {
        let p = BbobProblem::new(1, 5, 3).unwrap();
        assert_eq!(p.id(), "bbob_f001_i03_d05");
        assert_eq!(p.final_target_delta(), 1e-8);
        for _ in 0..7 {
            assert!(p.objective(&[0.0; 5]) > p.fopt());
        }
        assert_eq!(p.coco_evaluations(), 7);
        assert!(!p.final_target_hit());
    }
}
