//! Entry point: dispatch on the slave/master kinds.

use super::cell::Segmentation;
use super::clip_face_face::{ClipSlave, clip_prepared};
use super::face::{MortarFace, SegmentationSettings};
use super::segment_line_line::segment_line_line;
use crate::{Error, ErrorKind, GeometryKind};

/// Kratos `ExactMortarIntegrationUtility<TDim, TNumNodes, false, TNumNodesMaster>::
/// GetExactIntegration` (reference §10.2.1): the integration cells of the part of `master`
/// that overlaps `slave`, in the slave's local coordinates, or `None` where Kratos returns
/// `false` (no overlap, overlap of zero measure, a master beyond the distance threshold, and —
/// in 2D — the unexpected projection outcomes of Q44). `None` is what removes a pair from
/// `INDEX_MAP` in MappingCheck.
///
/// Supported pairs: Line2D2/Line2D2 (2D) and every combination of Triangle3D3 and
/// Quadrilateral3D4 (3D). In 3D the master nodes are projected along the slave condition normal
/// onto the plane through the slave centre and the polygons are clipped in that plane; in 2D the
/// slave nodes are projected onto the master along their nodal normals and the master nodes
/// onto the slave by Kratos' Newton iteration (`ProjectIterativeLine2D`). The master normal is
/// only used in 2D.
///
/// Errors: [`ErrorKind::Unsupported`] for another pair of kinds; [`ErrorKind::Degenerate`] for
/// a degenerate slave (zero length/area) or a zero (or in-plane) slave normal;
/// [`ErrorKind::NonFinite`] for a NaN distance threshold. A degenerate *master* is not an error:
/// it has no overlap of positive measure and gives what Kratos' NaN arithmetic gives (`None`,
/// except that Kratos mode keeps a master whose flattened projection lies entirely inside a
/// triangle slave, as Kratos does).
pub fn exact_segmentation(
    slave: &MortarFace<'_>,
    master: &MortarFace<'_>,
    settings: &SegmentationSettings,
) -> Result<Option<Segmentation>, Error> {
    SlaveSegmentation::new(slave, settings).segment(master)
}

/// [`exact_segmentation`] of one slave against each of its masters, with the slave's share of
/// the 3D clipping (its area, frame, projected and rotated nodes, the point-independent work
/// of its local coordinates) computed once: [`segment`](Self::segment) gives what
/// `exact_segmentation` gives, errors included (an error of the slave's share is reported by
/// every pair, at the point where `exact_segmentation` meets it).
#[derive(Debug)]
pub struct SlaveSegmentation<'s, 'f> {
    slave: &'s MortarFace<'f>,
    settings: SegmentationSettings,
    /// The slave's share of the 3D clipping (triangle and quadrilateral slaves).
    clip: Option<ClipSlave>,
}

impl<'s, 'f> SlaveSegmentation<'s, 'f> {
    /// Prepares the segmentations of `slave` with `settings`.
    pub fn new(slave: &'s MortarFace<'f>, settings: &SegmentationSettings) -> Self {
        use GeometryKind as K;
        let clip = (matches!(
            slave.geometry().kind(),
            K::Triangle3D3 | K::Quadrilateral3D4
        ) && !settings.distance_threshold.is_nan())
        .then(|| ClipSlave::new(slave, settings));
        SlaveSegmentation {
            slave,
            settings: *settings,
            clip,
        }
    }

    /// `exact_segmentation(slave, master, settings)`.
    pub fn segment(&self, master: &MortarFace<'_>) -> Result<Option<Segmentation>, Error> {
        use GeometryKind as K;
        let (slave, settings) = (self.slave, &self.settings);
        if settings.distance_threshold.is_nan() {
            return Err(Error::new(ErrorKind::NonFinite));
        }
        match (
            slave.geometry().kind(),
            master.geometry().kind(),
            &self.clip,
        ) {
            (K::Line2D2, K::Line2D2, _) => segment_line_line(slave, master, settings),
            (
                K::Triangle3D3 | K::Quadrilateral3D4,
                K::Triangle3D3 | K::Quadrilateral3D4,
                Some(clip),
            ) => clip_prepared(slave, clip, master, settings),
            _ => Err(Error::new(ErrorKind::Unsupported(
                "exact mortar segmentation of this pair of geometry kinds",
            ))),
        }
    }
}
