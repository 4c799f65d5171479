//! The contract of a scenario kind ([`crate::kinds`]): [`Kind`] (a kind's name, its tables
//! and how they become a [`Model`]) and [`Spec`] (what a validated model answers for the
//! generic layers), and [`Registry`], the list of kinds a scenario may name (softway's:
//! [`Registry::builtin`], in [`crate::kinds`]).

use super::error::ScenarioError;
use super::{Ctx, Run, RunSpec, Scenario};
use crate::contact::{FrictionLaw, Treatment};
use crate::growth::{GrowOptions, GrowthConfig, GrowthError, PassRunner};
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::run::results::Results;
use crate::time::Integrator;
use std::any::Any;
use std::path::Path;

/// Which setting a refusal is about: the error names that key.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Culprit {
    /// `time.integrator` (or `runs[i].integrator`).
    Integrator,
    /// `contact.method` (or `runs[i].method`).
    Contact,
}

/// A combination refused: the key at fault and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Refusal {
    /// The key the error names.
    pub culprit: Culprit,
    /// Why, and what to use instead.
    pub why: String,
}

/// A scenario kind: its name, its tables, and how they become a [`Model`].
pub trait Kind: Send + Sync {
    /// The name `kind = "..."` gives.
    fn name(&self) -> &'static str;

    /// The top-level tables it reads besides those every kind reads (`[time]`,
    /// `[[runs]]`, `[output]`, `[sweep]`, `[growth]`, `[wear]`); `"contact"` when it has
    /// a contact.
    fn tables(&self) -> &'static [&'static str];

    /// Its tables into a validated model, each value checked under its key.
    ///
    /// # Errors
    /// [`ScenarioError`] naming the file, the key and what is allowed.
    fn model(&self, input: &KindInput) -> Result<Model, ScenarioError>;

    /// The commands of its own studies ([`Spec::study`]: `"modes"`, `"receptance"`), for
    /// the message that refuses another kind; none by default.
    fn studies(&self) -> &'static [&'static str] {
        &[]
    }
}

/// What a kind's [`Kind::model`] reads: the scenario's text (each kind deserializes its own
/// tables from it, so that a misspelt key is named with its line) and the checks of
/// [`Ctx`].
pub struct KindInput<'a> {
    /// The checks, naming the scenario file.
    pub cx: &'a Ctx<'a>,
    /// The scenario's text.
    pub text: &'a str,
    /// Whether every run of the scenario runs the explicit central difference (top-level
    /// `time.integrator` and each `[[runs]]` entry's).
    pub every_run_explicit: bool,
}

impl KindInput<'_> {
    /// The kind's tables, deserialized from the whole text: `T` lists the tables as
    /// optional fields (without `deny_unknown_fields` at its top: the other tables are the
    /// other layers'); the tables' own structs deny unknown keys.
    ///
    /// # Errors
    /// [`ScenarioError::Parse`] with the line and the key.
    pub fn tables<T: serde::de::DeserializeOwned>(&self) -> Result<T, ScenarioError> {
        self.cx.parse_tables(self.text)
    }
}

/// The size of one run of a kind, for the cost estimate ([`crate::build::estimate`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Size {
    /// Degrees of freedom.
    pub dofs: f64,
    /// Duration simulated, s.
    pub duration: f64,
    /// Contact pairs (the contact solver's dense blocks grow with their square).
    pub contact_pairs: f64,
    /// The key that sets the size (`bar.elements`, `wheel.rim_nodes`, ...), named by the
    /// cost refusal.
    pub key: Option<&'static str>,
    /// The kind's own upper estimate of its factor's entries (a 3D model of a known shape);
    /// `None`: the generic one of its dimension ([`crate::build::factor_entries_3d`] in 3D).
    pub factor_entries: Option<f64>,
    /// The most columns `A^-1 e_d` a moving zone keeps for the run: one a dof its contact
    /// rows may touch; 0 without a moving zone. The run keeps at most
    /// [`crate::simulation::KEPT_COLUMNS_SHARE`] of the machine's memory of them.
    pub kept_columns: f64,
}

/// The model and the state and load of one free step (no contact), which `softway matrix`
/// writes out and times ([`Spec::free_step`]).
pub struct FreeStep {
    /// The model.
    pub model: crate::model::LinearModel,
    /// Its fixed dofs.
    pub fixed: Vec<usize>,
    /// The displacement.
    pub u0: Vec<f64>,
    /// The velocity.
    pub v0: Vec<f64>,
    /// The load.
    pub f: Vec<f64>,
}

/// One run as its kind checks it ([`Spec::check_run`]).
pub struct RunView<'a> {
    /// The run's own keys' prefix: `runs[i]`.
    pub index: usize,
    /// The integrator and its name as written.
    pub integrator: (&'a Integrator, &'a str),
    /// The contact treatment.
    pub contact: &'a Treatment,
    /// The friction law.
    pub friction: Option<FrictionLaw>,
    /// `alpha` and `gamma` of the space-time scheme.
    pub alpha_gamma: (f64, f64),
    /// The key `gamma` came from (`time.gamma` or `runs[i].gamma`).
    pub gamma_key: String,
}

/// A validated model of a kind: what the generic layers ask of it. Implemented by each
/// kind's model type (`Sdof`, `BarImpact`, `TwoBars`, `WheelScenario`, `TrackScenario`).
pub trait Spec: Any + std::fmt::Debug + Send + Sync {
    /// The kind's name (`kind = "..."`).
    fn kind(&self) -> &'static str;

    /// A copy in a box ([`Model`] is `Clone`).
    fn clone_spec(&self) -> Box<dyn Spec>;

    /// Whether `other` is the same model ([`Model`] is `PartialEq`).
    fn eq_spec(&self, other: &dyn Spec) -> bool;

    /// As [`Any`], for [`Model::get`].
    fn as_any(&self) -> &dyn Any;

    /// As [`Any`], for [`Model::get_mut`].
    fn as_any_mut(&mut self) -> &mut dyn Any;

    /// The dimension of its bodies' displacements (1 for a bar, 2 for the plane wheel and
    /// the rail); friction needs 2.
    fn dim(&self) -> usize;

    /// The run's end time, s, from `time.t_end` when given (a kind whose duration follows
    /// from its own keys refuses it).
    ///
    /// # Errors
    /// [`ScenarioError`] naming `time.t_end`.
    fn end_time(&self, cx: &Ctx, given: Option<f64>) -> Result<f64, ScenarioError>;

    /// The phrase of the step's refusal when it exceeds the run (`t_end`, s).
    fn end_phrase(&self, t_end: f64) -> String {
        format!("the step must not exceed time.t_end = {t_end}")
    }

    /// Checks the scenario as a whole: `runs` `[[runs]]` entries, whether `[contact]` is
    /// given.
    ///
    /// # Errors
    /// [`ScenarioError`] naming the key at fault.
    fn check_scenario(
        &self,
        _cx: &Ctx,
        _runs: usize,
        _contact_given: bool,
    ) -> Result<(), ScenarioError> {
        Ok(())
    }

    /// Why the model has no contact (its contact keys are refused), `None` when it has one.
    fn no_contact(&self) -> Option<&'static str> {
        None
    }

    /// The contact treatment when none is given.
    fn default_method(&self) -> &'static str {
        "soft_way"
    }

    /// The number of elements a run may set (`runs[i].elements`), with the table it
    /// belongs to: bars only.
    fn elements_mut(&mut self) -> Option<(&'static str, &mut usize)> {
        None
    }

    /// Why the model has no Coriolis term (`None`: it has one).
    fn coriolis(&self) -> Option<String> {
        Some("only a rotating wheel (kind = \"wheel\") has a Coriolis term".into())
    }

    /// The kind's rows of the table of combinations
    /// ([`crate::scenario::combinations::check_combination`]): `None` leaves the decision
    /// to the treatment's own rule.
    fn combination(
        &self,
        _integrator: &Integrator,
        _contact: &Treatment,
    ) -> Option<Result<(), Refusal>> {
        None
    }

    /// Checks the friction law given in `[contact]`.
    ///
    /// # Errors
    /// [`ScenarioError`] naming `contact.friction`.
    fn check_friction(&self, _cx: &Ctx, _law: FrictionLaw) -> Result<(), ScenarioError> {
        Ok(())
    }

    /// Checks one run's settings together (after the combination and the friction).
    ///
    /// # Errors
    /// [`ScenarioError`] naming the key at fault.
    fn check_run(&self, _cx: &Ctx, _run: &RunView) -> Result<(), ScenarioError> {
        Ok(())
    }

    /// The model for an explicit run (a lumped mass).
    fn make_explicit(&mut self) {}

    /// The step when none is given, s (`None`: `time.h` is required).
    fn default_step(&self) -> Option<f64> {
        None
    }

    /// Checks a fixed step `h` set by `key`.
    ///
    /// # Errors
    /// [`ScenarioError`] naming `key`.
    fn check_step(&self, _cx: &Ctx, _key: &str, _h: f64) -> Result<(), ScenarioError> {
        Ok(())
    }

    /// The central difference's stable step `2 / omega_max`, s, with a penalty spring
    /// (N/m) when given; infinite for a model without an explicit step of its own.
    fn explicit_stable_step(&self, _penalty: Option<f64>) -> f64 {
        f64::INFINITY
    }

    /// The lumped mass of the node an explicit penalty spring acts on, kg (infinite without
    /// one).
    fn explicit_contact_mass(&self) -> f64 {
        f64::INFINITY
    }

    /// The size of a run of this model; `mesh_nodes`: the nodes of a mesh file read by the
    /// caller.
    fn size(&self, run: &Run, mesh_nodes: Option<usize>) -> Size;

    /// A mesh file the cost estimate must read first (a wheel's Gmsh mesh): its nodes.
    ///
    /// # Errors
    /// The mesh's error.
    fn mesh_nodes(&self, _scenario: &Path) -> Result<Option<usize>, RunError> {
        Ok(None)
    }

    /// The pass runner of a growth study of `sc` (`softway grow`), with the `[growth]` keys
    /// it reads and none that it does not.
    ///
    /// # Errors
    /// [`GrowthError::Run`]: a kind without growth studies, a key of another runner, a key
    /// missing, a model that cannot be built.
    fn growth_runner(
        &self,
        sc: &Scenario,
        _config: &GrowthConfig,
        _opts: &GrowOptions,
    ) -> Result<Box<dyn PassRunner>, GrowthError> {
        Err(GrowthError::Run(RunError::input(
            &sc.path,
            format!("softway grow runs kind = \"wheel\" (the wheel on its rigid base) or kind = \"track\" with vehicle.model = \"wheel\", not kind = \"{}\"", self.kind()),
        )))
    }

    /// The kind's study that answers the command `command` (`"modes"`: a wheel's modes,
    /// `"receptance"`: a track's receptance); `None` (the default): the kind has none.
    fn study(&self, _command: &str) -> Option<&dyn Study> {
        None
    }

    /// The free step `softway matrix` writes out and times, for the run `run` of the
    /// scenario file `scenario`; `None`: the kind has none.
    ///
    /// # Errors
    /// [`RunError`]: a model that cannot be built.
    fn free_step(&self, _run: &Run, _scenario: &Path) -> Option<Result<FreeStep, RunError>> {
        None
    }

    /// Runs every run of `sc` (each of this kind); the long tables are streamed into
    /// `stream` when given.
    ///
    /// # Errors
    /// [`RunError`].
    fn record(
        &self,
        sc: &Scenario,
        stream: Option<&Path>,
        opts: &RunOptions,
    ) -> Result<Results, RunError>;
}

/// A validated model: a [`Spec`] of one of the kinds of the [`Registry`].
#[derive(Debug)]
pub struct Model(Box<dyn Spec>);

impl Model {
    /// A model of a kind's spec.
    pub fn new(spec: impl Spec) -> Self {
        Self(Box::new(spec))
    }

    /// The kind's name.
    pub fn kind(&self) -> &'static str {
        self.0.kind()
    }

    /// The model as its kind's type, when it is one.
    pub fn get<T: Spec>(&self) -> Option<&T> {
        self.0.as_any().downcast_ref()
    }

    /// The model as its kind's type, when it is one, to change.
    pub fn get_mut<T: Spec>(&mut self) -> Option<&mut T> {
        self.0.as_any_mut().downcast_mut()
    }

    /// The spec.
    pub fn spec(&self) -> &dyn Spec {
        &*self.0
    }

    /// The spec, to change.
    pub fn spec_mut(&mut self) -> &mut dyn Spec {
        &mut *self.0
    }
}

impl std::ops::Deref for Model {
    type Target = dyn Spec;
    fn deref(&self) -> &Self::Target {
        &*self.0
    }
}

impl std::ops::DerefMut for Model {
    fn deref_mut(&mut self) -> &mut Self::Target {
        &mut *self.0
    }
}

impl Clone for Model {
    fn clone(&self) -> Self {
        Self(self.0.clone_spec())
    }
}

impl PartialEq for Model {
    fn eq(&self, other: &Self) -> bool {
        self.0.eq_spec(&*other.0)
    }
}

/// The `Spec` plumbing of a model type that is `Clone + PartialEq`: `kind`, `clone_spec`,
/// `eq_spec`, `as_any`, `as_any_mut`.
#[macro_export]
macro_rules! spec_plumbing {
    ($name:expr) => {
        fn kind(&self) -> &'static str {
            $name
        }
        fn clone_spec(&self) -> Box<dyn $crate::scenario::kind::Spec> {
            Box::new(self.clone())
        }
        fn eq_spec(&self, other: &dyn $crate::scenario::kind::Spec) -> bool {
            other
                .as_any()
                .downcast_ref::<Self>()
                .is_some_and(|o| o == self)
        }
        fn as_any(&self) -> &dyn std::any::Any {
            self
        }
        fn as_any_mut(&mut self) -> &mut dyn std::any::Any {
            self
        }
    };
}

/// The list of kinds a scenario may name: the only one.
#[derive(Clone)]
pub struct Registry {
    kinds: Vec<&'static dyn Kind>,
}

impl Registry {
    /// A list of kinds (softway's own: [`Registry::builtin`]).
    pub fn new(kinds: Vec<&'static dyn Kind>) -> Self {
        Self { kinds }
    }

    /// This list with one kind more (a kind of one's own; it replaces a kind of the same
    /// name).
    pub fn with(mut self, kind: &'static dyn Kind) -> Self {
        self.kinds.retain(|k| k.name() != kind.name());
        self.kinds.push(kind);
        self
    }

    /// The kind named `name`.
    pub fn get(&self, name: &str) -> Option<&'static dyn Kind> {
        self.kinds.iter().copied().find(|k| k.name() == name)
    }

    /// The kinds, in order.
    pub fn kinds(&self) -> impl Iterator<Item = &'static dyn Kind> + '_ {
        self.kinds.iter().copied()
    }

    /// The names of the kinds whose study answers `command` ([`Kind::studies`]).
    pub fn answering(&self, command: &str) -> Vec<&'static str> {
        self.kinds
            .iter()
            .filter(|k| k.studies().contains(&command))
            .map(|k| k.name())
            .collect()
    }

    /// The names, quoted and joined (`"sdof", "bar_impact", ...`), for messages.
    pub fn names(&self) -> String {
        self.kinds
            .iter()
            .map(|k| format!("\"{}\"", k.name()))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// A study of a kind's own that a command runs into a staged output folder: `softway modes`
/// of a wheel, `softway receptance` of a track ([`Spec::study`]). The command reads the
/// scenario, stages the folder, hands the study its first run's model and prints what it
/// returns; the folder rules, the scenario's copy and the interruption are the command's.
pub trait Study: Sync {
    /// Runs the study of the scenario `sc` (its first run's model, before the runs are
    /// resolved) into the folder `dir`.
    ///
    /// # Errors
    /// [`RunError`]: a model that cannot be built, a bad option, a failed write.
    fn run(
        &self,
        sc: &Scenario<RunSpec>,
        opts: &StudyOptions,
        dir: &Path,
    ) -> Result<StudyReport, RunError>;
}

/// What a [`Study`] is asked for.
#[derive(Debug, Clone, Copy)]
pub struct StudyOptions<'a> {
    /// `--count`: how many results (modes) the study gives, where it takes a count.
    pub count: Option<usize>,
    /// Whether to draw the figures.
    pub plots: bool,
    /// Set by SIGINT, SIGTERM or SIGHUP: the study stops at its next point.
    pub cancel: &'a std::sync::atomic::AtomicBool,
}

/// What a [`Study`] gives back.
#[derive(Debug, Clone, Default)]
pub struct StudyReport {
    /// Lines for the screen (tables), printed before the files.
    pub lines: Vec<String>,
    /// The files written into the folder.
    pub files: Vec<std::path::PathBuf>,
    /// Stopped by a signal before its end: what the folder then holds.
    pub interrupted: Option<String>,
}
