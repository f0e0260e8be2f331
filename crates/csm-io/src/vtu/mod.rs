//! VTU (VTK XML UnstructuredGrid) writer.

mod cell_type;
mod write_vtu;

pub use cell_type::vtk_cell_type;
pub use write_vtu::{DataArray, VtuFormat, VtuWriter};
