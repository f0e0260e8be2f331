//! Small contact scenes built in code for the stability suite, written as `.mdpa` text (so a
//! transformed scene is exactly what a user would give csm), and the rigid motions and uniform
//! scalings applied to a mesh's node lines.
//!
//! A scene is made of *sheets*: a structured grid of contact-surface points, extruded by a
//! thickness against its outward normal into one layer of Hexahedra3D8 (Quadrilateral3D4
//! contact faces) or Prism3D6 (Triangle3D3 faces), so that every node is in an element
//! (FindNodalHProcess gives every node a finite NODAL_H) and the faces point out of their body.

use std::fmt::Write as _;

use csm::prelude::{Point, Real, Vector};

/// A structured grid of contact-surface points, `grid[j][i]`, and how it is extruded.
#[derive(Debug, Clone)]
pub struct Sheet {
    /// The contact-surface points, rows of equal length.
    pub grid: Vec<Vec<Point>>,
    /// The outward normal of the contact faces (the body lies on the other side).
    pub out: Vector,
    /// The thickness of the layer of solids behind the faces.
    pub thickness: Real,
    /// Triangles (each cell split in two) instead of quadrilaterals.
    pub triangles: bool,
}

impl Sheet {
    /// A flat sheet: points `origin + xs[i]·ex + ys[j]·ey`.
    pub fn flat(origin: Point, ex: Vector, ey: Vector, xs: &[Real], ys: &[Real]) -> Sheet {
        let grid = ys
            .iter()
            .map(|&y| xs.iter().map(|&x| origin + ex * x + ey * y).collect())
            .collect();
        Sheet {
            grid,
            out: ex.cross(&ey).normalize(),
            thickness: 1.0,
            triangles: false,
        }
    }

    /// The same sheet facing the other way (its body on the other side).
    pub fn flipped(mut self) -> Sheet {
        self.out = -self.out;
        self
    }

    /// With triangular faces.
    pub fn triangles(mut self) -> Sheet {
        self.triangles = true;
        self
    }

    /// With thickness `t`.
    pub fn thick(mut self, t: Real) -> Sheet {
        self.thickness = t;
        self
    }
}

/// `n + 1` equally spaced values from `a` to `b`.
pub fn linspace(a: Real, b: Real, n: usize) -> Vec<Real> {
    (0..=n)
        .map(|i| a + (b - a) * i as Real / n as Real)
        .collect()
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum SolidKind {
    Hexahedron,
    Prism,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum FaceKind {
    Quadrilateral,
    Triangle,
}

/// A 3D scene: the parts `Slave` and `Master` (conditions and their nodes) and the solids
/// behind them. Ids are 1-based, in creation order.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    nodes: Vec<Point>,
    solids: Vec<(SolidKind, Vec<u32>)>,
    /// (kind, nodes, is slave)
    faces: Vec<(FaceKind, Vec<u32>, bool)>,
}

impl Scene {
    /// An empty scene.
    pub fn new() -> Scene {
        Scene::default()
    }

    fn node(&mut self, p: Point) -> u32 {
        self.nodes.push(p);
        self.nodes.len() as u32
    }

    /// Adds `sheet` to the slave (`slave`) or master part.
    pub fn sheet(mut self, sheet: &Sheet, slave: bool) -> Scene {
        let rows = sheet.grid.len();
        let cols = sheet.grid[0].len();
        let front: Vec<Vec<u32>> = sheet
            .grid
            .iter()
            .map(|row| row.iter().map(|&p| self.node(p)).collect())
            .collect();
        let back: Vec<Vec<u32>> = sheet
            .grid
            .iter()
            .map(|row| {
                row.iter()
                    .map(|&p| self.node(p - sheet.out * sheet.thickness))
                    .collect()
            })
            .collect();
        for j in 0..rows - 1 {
            for i in 0..cols - 1 {
                let cell = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                let polys: Vec<Vec<usize>> = if sheet.triangles {
                    vec![vec![0, 1, 2], vec![0, 2, 3]]
                } else {
                    vec![vec![0, 1, 2, 3]]
                };
                for poly in polys {
                    let mut corners: Vec<(usize, usize)> = poly.iter().map(|&k| cell[k]).collect();
                    // Counter-clockwise seen from outside, so that the face normal is `out`.
                    let p = |c: &(usize, usize)| sheet.grid[c.1][c.0];
                    let n = newell(&corners.iter().map(p).collect::<Vec<_>>());
                    if n.dot(&sheet.out) < 0.0 {
                        corners.reverse();
                    }
                    let f: Vec<u32> = corners.iter().map(|c| front[c.1][c.0]).collect();
                    let b: Vec<u32> = corners.iter().map(|c| back[c.1][c.0]).collect();
                    // Solid: the back face first (counter-clockwise seen from the front).
                    let mut solid = b.clone();
                    solid.extend(&f);
                    let (sk, fk) = if sheet.triangles {
                        (SolidKind::Prism, FaceKind::Triangle)
                    } else {
                        (SolidKind::Hexahedron, FaceKind::Quadrilateral)
                    };
                    self.solids.push((sk, solid));
                    self.faces.push((fk, f, slave));
                }
            }
        }
        self
    }

    /// The number of nodes so far.
    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// The scene with the nodes from index `first` on moved by `f`.
    pub fn map_from(mut self, first: usize, f: impl Fn(Point) -> Point) -> Scene {
        for p in &mut self.nodes[first..] {
            *p = f(*p);
        }
        self
    }

    /// The `.mdpa` text: nodes, elements and conditions by kind, the parts `Slave` and
    /// `Master`.
    pub fn to_mdpa(&self) -> String {
        let mut s = String::from("Begin Properties 0\nEnd Properties\n\nBegin Nodes\n");
        for (i, p) in self.nodes.iter().enumerate() {
            let _ = writeln!(s, "{} {:?} {:?} {:?}", i + 1, p.x, p.y, p.z);
        }
        s.push_str("End Nodes\n");
        let mut id = 0;
        for kind in [SolidKind::Hexahedron, SolidKind::Prism] {
            let rows: Vec<_> = self.solids.iter().filter(|(k, _)| *k == kind).collect();
            if rows.is_empty() {
                continue;
            }
            let name = match kind {
                SolidKind::Hexahedron => "Element3D8N",
                SolidKind::Prism => "Element3D6N",
            };
            let _ = writeln!(s, "Begin Elements {name}");
            for (_, nodes) in rows {
                id += 1;
                let _ = writeln!(s, "{id} 0 {}", join(nodes));
            }
            s.push_str("End Elements\n");
        }
        let mut ids = Vec::new();
        let mut id = 0;
        for kind in [FaceKind::Quadrilateral, FaceKind::Triangle] {
            let rows: Vec<_> = self.faces.iter().filter(|(k, ..)| *k == kind).collect();
            if rows.is_empty() {
                continue;
            }
            let name = match kind {
                FaceKind::Quadrilateral => "SurfaceCondition3D4N",
                FaceKind::Triangle => "SurfaceCondition3D3N",
            };
            let _ = writeln!(s, "Begin Conditions {name}");
            for (_, nodes, slave) in rows {
                id += 1;
                ids.push((id, nodes, *slave));
                let _ = writeln!(s, "{id} 0 {}", join(nodes));
            }
            s.push_str("End Conditions\n");
        }
        for (part, slave) in [("Slave", true), ("Master", false)] {
            let mut nodes: Vec<u32> = ids
                .iter()
                .filter(|(_, _, sl)| *sl == slave)
                .flat_map(|(_, n, _)| n.iter().copied())
                .collect();
            nodes.sort_unstable();
            nodes.dedup();
            let conds: Vec<u32> = ids
                .iter()
                .filter(|(_, _, sl)| *sl == slave)
                .map(|(i, ..)| *i)
                .collect();
            let _ = writeln!(
                s,
                "Begin SubModelPart {part}\n  Begin SubModelPartNodes\n{}\n  End SubModelPartNodes\n  Begin SubModelPartConditions\n{}\n  End SubModelPartConditions\nEnd SubModelPart",
                join(&nodes),
                join(&conds)
            );
        }
        s
    }
}

fn join(ids: &[u32]) -> String {
    ids.iter().map(u32::to_string).collect::<Vec<_>>().join(" ")
}

/// Newell's normal of a polygon (not normalised).
fn newell(p: &[Point]) -> Vector {
    let mut n = Vector::zeros();
    for i in 0..p.len() {
        n += p[i].coords.cross(&p[(i + 1) % p.len()].coords);
    }
    n
}

/// Applies `f` to every node line of an `.mdpa` text (`id x y z` between `Begin Nodes` and
/// `End Nodes`); coordinates are written so that they read back exactly.
pub fn map_mdpa(text: &str, f: impl Fn(Point) -> Point) -> String {
    let mut out = String::with_capacity(text.len() + text.len() / 4);
    let mut in_nodes = false;
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with("Begin Nodes") {
            in_nodes = true;
        } else if t.starts_with("End Nodes") {
            in_nodes = false;
        } else if in_nodes && !t.is_empty() && !t.starts_with("//") {
            let w: Vec<&str> = t.split_whitespace().collect();
            if let (4, Ok(x), Ok(y), Ok(z)) = (
                w.len(),
                w[1].parse::<Real>(),
                w[2].parse::<Real>(),
                w[3].parse::<Real>(),
            ) {
                let p = f(Point::new(x, y, z));
                let _ = writeln!(out, "{} {:?} {:?} {:?}", w[0], p.x, p.y, p.z);
                continue;
            }
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}
