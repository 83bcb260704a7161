//! The validation lab: simulated CMR acquisitions of reference shapes (with known ground truth),
//! leave-one-out, and the small geometric tools they need (plane sections, a seeded generator, a
//! convex hull baseline). Follows the validation protocol of Villard, Grau & Zacur (J. Imaging 2018).

pub mod axis;
pub mod cavity;
pub mod experiment;
pub mod experiment_design;
pub mod hull;
pub mod leave_one_out;
pub mod planes;
pub mod population;
pub mod prng;
pub mod repair;
pub mod segmentation;
pub mod shapes;
pub mod slice;

pub use axis::LongAxis;
pub use planes::{simulate, Acquisition, AcquisitionSpec, Misalignment, SaxStack};
pub use slice::{slice_mesh, Plane};
