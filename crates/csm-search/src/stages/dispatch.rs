//! Stage 4: which search-process instance a pair runs (Kratos `ContactSearchWrapperProcess`,
//! reference §2): by DOMAIN_SIZE and the node counts of the slave and master conditions.

use csm_model::{Flag, ModelPart, PartIdx};

use crate::error::{Error, ErrorKind};

/// The template instance of Kratos' search process: `<dim, slave nodes, master nodes>`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SearchInstance {
    /// 2 or 3.
    pub dim: u8,
    /// Nodes of a slave condition as the search sees it (6 → 3 for quadratic triangles).
    pub slave_nodes: u8,
    /// Nodes of a master condition as the search sees it.
    pub master_nodes: u8,
}

impl SearchInstance {
    /// Kratos' class-name suffix, e.g. `3D3N4N` (`<3,3,4>`) or `2D2N`.
    pub fn suffix(&self) -> String {
        if self.slave_nodes == self.master_nodes {
            format!("{}D{}N", self.dim, self.slave_nodes)
        } else {
            format!("{}D{}N{}N", self.dim, self.slave_nodes, self.master_nodes)
        }
    }
}

/// Chooses the instance for the conditions of `contact` (the whole `Contact` part, as Kratos
/// scans it). `domain_size` is ProcessInfo DOMAIN_SIZE (0 if unset: the 3D branch, as Kratos).
///
/// Predefined roles: the node counts of the last MASTER and the last SLAVE condition seen
/// until both are known; otherwise the first condition's count for both. A count of 6
/// becomes 3 (Kratos' warning: quadratic triangles searched through their corner
/// subtriangulation). 2D always gives `<2,2,2>` (3-node lines too). In 3D only 3/3, 4/4,
/// 3/4 and 4/3 exist; Kratos leaves a null process for any other combination and crashes on
/// the first hook (Q31) — here it is an error naming the counts.
pub fn dispatch(
    model: &ModelPart,
    contact: PartIdx,
    domain_size: u32,
    predefined: bool,
) -> Result<SearchInstance, Error> {
    let conditions = model.conditions();
    let (mut master, mut slave) = (0usize, 0usize);
    for c in model.part(contact).conditions() {
        let n = conditions.nodes(c.index()).len();
        let flags = conditions.flags()[c.index()];
        if predefined {
            if flags.is(Flag::MASTER) {
                master = n;
            }
            if flags.is(Flag::SLAVE) {
                slave = n;
            }
            if master != 0 && slave != 0 {
                break;
            }
        } else {
            master = n;
            slave = n;
            break;
        }
    }
    let reduce = |n: usize| if n == 6 { 3 } else { n };
    let (slave, master) = (reduce(slave), reduce(master));
    if domain_size == 2 {
        return Ok(SearchInstance {
            dim: 2,
            slave_nodes: 2,
            master_nodes: 2,
        });
    }
    match (slave, master) {
        (3, 3) | (4, 4) | (3, 4) | (4, 3) => Ok(SearchInstance {
            dim: 3,
            slave_nodes: slave as u8,
            master_nodes: master as u8,
        }),
        (s, m) => Err(ErrorKind::RejectedByKratos(format!(
            "no contact search for slave conditions of {s} nodes and master conditions of {m} \
             nodes in 3D (Kratos supports 3/3, 4/4, 3/4 and 4/3, with 6-node triangles searched \
             as 3-node ones; it leaves a null process here and crashes, Q31)"
        ))
        .into()),
    }
}

#[cfg(test)]
mod tests;
