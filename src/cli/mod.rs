//! The commands of the `csm` binary, as library functions over explicit data so that tests
//! can call them without a process.

mod demo;
mod info;
pub mod logger;
pub mod profile;
mod progress;
mod report;
mod search;
mod vtk;

pub use demo::{
    DEFAULT_FACES, DemoScene, DemoTruth, MAX_FACES, demo_scene, demo_summary, demo_truth,
};
pub use info::{MeshInfo, PartInfo, mesh_info};
pub use progress::{Progress, progress_wanted};
pub use report::{
    Report, ReportOptions, ReportText, Row, Strategy, TruthSummary, run_report, strategies,
};
pub use search::{
    RunOptions, Timings, default_setup, load_setup, run_search, run_search_with, search_plan,
    setup_for,
};
pub use vtk::{search_vtu, write_search_vtu};
