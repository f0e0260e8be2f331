//! `cargo xtask scene`: the benchmark's stacked blocks written by Rust, for sizes the Python
//! generator (`tools/bench_scenes.py`, about 50 s per 1e5 slave faces on the 2-core machine)
//! is too slow for: the rank sweeps' 1e6-face scenes, made on the machine that runs them.
//!
//! The scene and the file are the same as `bench_scenes.py stacked_blocks:N` writes, byte for
//! byte but the comment lines and the spelling of a coordinate under 1e-4 (Python's `repr`
//! writes `1e-05`, Rust `1e-5`: the same double): two non-matching structured hexahedral slabs,
//! upper `[0, 1]^2 x [0, h]` with `n x n` slave quads (`n = round(sqrt(N))`), lower
//! `[-0.05, 1.05]^2 x [-h, 0]` with `m x m` master quads (`m = round(0.83 n)`), the interface
//! exactly on `z = 0`. A test compares the two generators where Python is there.

use std::fmt::Write as _;
use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

/// `cargo xtask scene`'s arguments.
#[derive(Debug, clap::Args)]
pub struct Options {
    /// The scene: only `stacked_blocks` (the sphere needs gmsh: `tools/bench_scenes.py`).
    scene: String,
    /// About how many slave faces (`n = round(sqrt(N))` per side).
    slave_faces: f64,
    /// The `.mdpa` file to write.
    output: PathBuf,
}

/// Writes the scene the options name.
pub fn scene(options: &Options) -> Result<()> {
    if options.scene != "stacked_blocks" {
        bail!(
            "unknown scene '{}': `cargo xtask scene` writes stacked_blocks only \
             (the sphere on a plate needs gmsh: tools/bench_scenes.py)",
            options.scene
        );
    }
    if !(options.slave_faces.is_finite() && options.slave_faces >= 1.0) {
        bail!(
            "slave faces must be a number ≥ 1, not {}",
            options.slave_faces
        );
    }
    let (slave, master) = write_stacked_blocks(options.slave_faces as usize, &options.output)?;
    println!("{} {slave} {master}", options.output.display());
    Ok(())
}

/// The mesh being built: node coordinates and hexahedra, in creation order (ids from 1).
#[derive(Default)]
struct Mesh {
    nodes: Vec<[f64; 3]>,
    elements: Vec<[usize; 8]>,
    conditions: Vec<[usize; 4]>,
}

/// One slab's elements and contact-face conditions (ids).
struct Slab {
    elements: std::ops::Range<usize>,
    conditions: std::ops::Range<usize>,
}

impl Mesh {
    fn add_node(&mut self, xyz: [f64; 3]) -> usize {
        self.nodes.push(xyz);
        self.nodes.len()
    }

    /// `n x n` hexahedra over `[x0, x1]^2` between `z_face` (the contact face) and `z_back`,
    /// node and face numbering as `bench_scenes.quad_slab`.
    fn quad_slab(&mut self, x0: f64, x1: f64, n: usize, z_face: f64, z_back: f64) -> Slab {
        let mut top = vec![0; (n + 1) * (n + 1)];
        let mut bottom = vec![0; (n + 1) * (n + 1)];
        for j in 0..=n {
            for i in 0..=n {
                let x = x0 + (x1 - x0) * i as f64 / n as f64;
                let y = x0 + (x1 - x0) * j as f64 / n as f64;
                top[j * (n + 1) + i] = self.add_node([x, y, z_face.max(z_back)]);
                bottom[j * (n + 1) + i] = self.add_node([x, y, z_face.min(z_back)]);
            }
        }
        let (e0, c0) = (self.elements.len() + 1, self.conditions.len() + 1);
        let up = z_face > z_back;
        for j in 0..n {
            for i in 0..n {
                let q =
                    [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)].map(|(a, b)| b * (n + 1) + a);
                let (t, b) = (q.map(|k| top[k]), q.map(|k| bottom[k]));
                self.elements
                    .push([b[0], b[1], b[2], b[3], t[0], t[1], t[2], t[3]]);
                self.conditions
                    .push(if up { t } else { [b[3], b[2], b[1], b[0]] });
            }
        }
        Slab {
            elements: e0..self.elements.len() + 1,
            conditions: c0..self.conditions.len() + 1,
        }
    }
}

/// Writes the stacked blocks with about `slave_faces` slave quads to `path`; returns the
/// slave and master face counts.
fn write_stacked_blocks(slave_faces: usize, path: &Path) -> Result<(usize, usize)> {
    let n = ((slave_faces as f64).sqrt().round() as usize).max(2);
    let m = ((0.83 * n as f64).round() as usize).max(2);
    let h = 1.0 / n as f64;
    let mut mesh = Mesh::default();
    let upper = mesh.quad_slab(0.0, 1.0, n, 0.0, h);
    let lower = mesh.quad_slab(-0.05, 1.05, m, 0.0, -h);

    let file = fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut f = BufWriter::with_capacity(1 << 20, file);
    let mut line = String::new();
    writeln!(
        f,
        "// csm benchmark scene 'stacked_blocks' (cargo xtask scene, do not edit), h = {h:?}\n\
         // {} nodes, {} elements, {} slave and {} master faces",
        mesh.nodes.len(),
        mesh.elements.len(),
        n * n,
        m * m
    )?;
    f.write_all(
        b"Begin ModelPartData\n//  VARIABLE_NAME value\nEnd ModelPartData\n\n\
          Begin Properties 0\nEnd Properties\n\nBegin Nodes\n",
    )?;
    for (i, [x, y, z]) in mesh.nodes.iter().enumerate() {
        line.clear();
        writeln!(line, "{} {x:?} {y:?} {z:?}", i + 1)?;
        f.write_all(line.as_bytes())?;
    }
    f.write_all(b"End Nodes\n\nBegin Elements Element3D8N\n")?;
    for (i, nodes) in mesh.elements.iter().enumerate() {
        write_entity(&mut f, &mut line, i + 1, nodes)?;
    }
    f.write_all(b"End Elements\n\nBegin Conditions SurfaceCondition3D4N\n")?;
    for (i, nodes) in mesh.conditions.iter().enumerate() {
        write_entity(&mut f, &mut line, i + 1, nodes)?;
    }
    f.write_all(b"End Conditions\n\n")?;
    let parts = [
        ("Parts_Slave", 0..0, upper.conditions.clone()),
        ("Parts_Master", 0..0, lower.conditions.clone()),
        ("Parts_Upper", upper.elements.clone(), 0..0),
        ("Parts_Lower", lower.elements.clone(), 0..0),
    ];
    for (name, elements, conditions) in parts {
        let mut nodes: Vec<usize> = elements
            .clone()
            .flat_map(|e| mesh.elements[e - 1])
            .chain(conditions.clone().flat_map(|c| mesh.conditions[c - 1]))
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        writeln!(f, "Begin SubModelPart {name}\n  Begin SubModelPartNodes")?;
        for id in nodes {
            writeln!(f, "    {id}")?;
        }
        f.write_all(b"  End SubModelPartNodes\n  Begin SubModelPartElements\n")?;
        for id in elements {
            writeln!(f, "    {id}")?;
        }
        f.write_all(b"  End SubModelPartElements\n  Begin SubModelPartConditions\n")?;
        for id in conditions {
            writeln!(f, "    {id}")?;
        }
        f.write_all(b"  End SubModelPartConditions\nEnd SubModelPart\n\n")?;
    }
    f.flush()
        .with_context(|| format!("writing {}", path.display()))?;
    Ok((n * n, m * m))
}

/// One `id 0 node…` line of an element or condition block.
fn write_entity(f: &mut impl Write, line: &mut String, id: usize, nodes: &[usize]) -> Result<()> {
    line.clear();
    write!(line, "{id} 0")?;
    for k in nodes {
        write!(line, " {k}")?;
    }
    line.push('\n');
    f.write_all(line.as_bytes())?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Rust scene equals `bench_scenes.py`'s (but its comment lines), where `python3` is
    /// there; the file is always checked for its counts.
    #[test]
    fn stacked_blocks_match_the_python_generator() {
        let dir = std::env::temp_dir().join(format!("csm-xtask-scene-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let rust = dir.join("rust.mdpa");
        let (slave, master) = write_stacked_blocks(300, &rust).unwrap();
        assert_eq!((slave, master), (17 * 17, 14 * 14));
        let text = fs::read_to_string(&rust).unwrap();
        let body = |t: &str| -> String {
            t.lines()
                .filter(|l| !l.starts_with("// "))
                .collect::<Vec<_>>()
                .join("\n")
        };
        assert!(text.contains("Begin SubModelPart Parts_Lower"));
        let tools = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tools");
        let script = format!(
            "import sys; sys.path.insert(0, {:?}); import bench_scenes as b; \
             m, h = b.stacked_blocks(300); m.write({:?}, 'x')",
            tools.display().to_string(),
            dir.join("python.mdpa").display().to_string()
        );
        match std::process::Command::new("python3")
            .args(["-c", &script])
            .status()
        {
            Ok(s) if s.success() => {
                let python = fs::read_to_string(dir.join("python.mdpa")).unwrap();
                assert_eq!(body(&text), body(&python));
            }
            _ => eprintln!(
                "python3 missing or failing: the comparison with bench_scenes.py is skipped"
            ),
        }
        fs::remove_dir_all(&dir).unwrap();
    }
}
