//! Contact diagnostics of a discrete solution against an exact contact solution
//! (`docs/manufactured.md`, section 8): resultants, nodal pressure, the discrete switch points and
//! the expected active and stick/slip sets.
//!
//! Conventions (`docs/formulation.md`, section 4, and `vem_contact`): the nodal contact force
//! `lambda_N >= 0` approximates `-sigma_nu` times the tributary length, so
//! `sum lambda_N -> -int sigma_nu ds`; the nodal friction force on body one along `tau = e_x`
//! approximates `sigma_1tau` times the tributary length, so its sum tends to
//! `int sigma_1tau ds`.
//!
//! Switch points. The transitions of M1 and M2 are flat by design, so nodes just past the
//! exact switch point may legitimately take either status; the discrete switch point is the
//! last active node (contact/separation) or the first slipping node (stick/slip) along
//! `Gamma_C`, reported with its distance to the exact point, not asserted.

use serde::{Deserialize, Serialize};
use vem_contact::{InterfaceNode, NodeStatus};
use vem_space::quadrature::GaussLegendre;

use crate::exact::{ContactSet, ExactContact, FrictionSet, Resultants};

/// Subintervals of the composite Gauss rule for resultants without a closed form.
const RESULTANT_INTERVALS: usize = 512;

/// An exact switch point and the discrete one.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SwitchPoint {
    /// The exact abscissa.
    pub exact: f64,
    /// The abscissa of the last active node (contact/separation) or of the first slipping node
    /// (stick/slip); `None` when no node has that status.
    pub discrete: Option<f64>,
    /// `|discrete - exact|` (`None` with `discrete`).
    pub distance: Option<f64>,
}

impl SwitchPoint {
    fn new(exact: f64, discrete: Option<f64>) -> Self {
        Self {
            exact,
            discrete,
            distance: discrete.map(|x| (x - exact).abs()),
        }
    }
}

/// An interface node whose status contradicts the expected sets.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SetViolation {
    /// The node's abscissa on `Gamma_C`.
    pub x: f64,
    /// The status it must have ("active", "open", "stick", "slip").
    pub expected: String,
    /// Its status ("open", "stick", "slip").
    pub found: String,
}

/// What the interface nodes of a discrete contact solution say, against the exact solution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContactDiagnostics {
    /// Interface nodes (node pairs).
    pub nodes: usize,
    /// Nodes in contact (contact, stick or slip).
    pub active: usize,
    /// Nodes in contact without friction (frictionless law).
    #[serde(default)]
    pub contact: usize,
    /// Nodes in contact that stick (friction below its bound).
    pub stick: usize,
    /// Nodes in contact that slip (friction at its bound).
    pub slip: usize,
    /// `sum lambda_N`, the discrete normal resultant.
    pub normal_resultant: f64,
    /// `-int sigma_nu ds`, its exact value.
    pub normal_resultant_exact: f64,
    /// `|sum lambda_N + int sigma_nu ds|`.
    pub normal_resultant_error: f64,
    /// `sum` of the nodal friction forces on body one along `tau`.
    pub tangential_resultant: f64,
    /// `int sigma_1tau ds`.
    pub tangential_resultant_exact: f64,
    /// `|sum friction force - int sigma_1tau ds|`.
    pub tangential_resultant_error: f64,
    /// `(sum_x l_x (lambda_N / l_x + sigma_nu(x))^2)^(1/2)`: the nodal pressure error in a
    /// discrete L2(Gamma_C) norm.
    pub pressure_error: f64,
    /// Contact/separation switch (cases with a split contact set).
    pub contact_switch: Option<SwitchPoint>,
    /// Stick/slip switch (Tresca cases with a split friction set).
    pub slip_switch: Option<SwitchPoint>,
    /// Nodes whose status contradicts the expected sets (empty when none are known).
    pub set_violations: Vec<SetViolation>,
}

/// The diagnostics of the interface nodes `nodes` of a discrete solution of `exact`.
pub fn contact_diagnostics(
    exact: &dyn ExactContact,
    nodes: &[InterfaceNode],
) -> ContactDiagnostics {
    let reference = exact
        .reference_resultants()
        .unwrap_or_else(|| integrated_resultants(exact));
    let normal_resultant: f64 = nodes.iter().map(|n| n.normal_force).sum();
    let tangential_resultant: f64 = nodes.iter().map(|n| n.friction_t()).sum();
    let pressure_error = nodes
        .iter()
        .map(|n| {
            let sigma_nu = exact.interface_values(n.position.x).sigma_nu;
            n.tributary_measure * (n.pressure + sigma_nu).powi(2)
        })
        .sum::<f64>()
        .sqrt();
    let count = |status: NodeStatus| nodes.iter().filter(|n| n.status == status).count();
    let active_x = nodes
        .iter()
        .filter(|n| n.status != NodeStatus::Open)
        .map(|n| n.position.x);
    let slip_x = nodes
        .iter()
        .filter(|n| n.status == NodeStatus::Slip)
        .map(|n| n.position.x);
    let sets = exact.expected_sets();
    let contact_switch = match sets.map(|s| s.contact) {
        Some(ContactSet::Split { switch_point, .. }) => {
            Some(SwitchPoint::new(switch_point, active_x.reduce(f64::max)))
        }
        _ => None,
    };
    let slip_switch = match sets.and_then(|s| s.friction) {
        Some(FrictionSet::Split { switch_point, .. }) => {
            Some(SwitchPoint::new(switch_point, slip_x.reduce(f64::min)))
        }
        _ => None,
    };
    let mut set_violations = Vec::new();
    if let Some(sets) = sets {
        for n in nodes {
            let x = n.position.x;
            let found = n.status.name().to_string();
            let active = n.status != NodeStatus::Open;
            match sets.contact.expects_active(x) {
                Some(true) if !active => set_violations.push(SetViolation {
                    x,
                    expected: "active".into(),
                    found: found.clone(),
                }),
                Some(false) if active => set_violations.push(SetViolation {
                    x,
                    expected: "open".into(),
                    found: found.clone(),
                }),
                _ => {}
            }
            if let (Some(friction), true) = (sets.friction, active) {
                let slips = n.status == NodeStatus::Slip;
                match friction.expects_slip(x) {
                    Some(true) if !slips => set_violations.push(SetViolation {
                        x,
                        expected: "slip".into(),
                        found,
                    }),
                    Some(false) if slips => set_violations.push(SetViolation {
                        x,
                        expected: "stick".into(),
                        found,
                    }),
                    _ => {}
                }
            }
        }
    }
    ContactDiagnostics {
        nodes: nodes.len(),
        active: nodes.len() - count(NodeStatus::Open),
        contact: count(NodeStatus::Contact),
        stick: count(NodeStatus::Stick),
        slip: count(NodeStatus::Slip),
        normal_resultant,
        normal_resultant_exact: -reference.normal,
        normal_resultant_error: (normal_resultant + reference.normal).abs(),
        tangential_resultant,
        tangential_resultant_exact: reference.tangential,
        tangential_resultant_error: (tangential_resultant - reference.tangential).abs(),
        pressure_error,
        contact_switch,
        slip_switch,
        set_violations,
    }
}

/// `int sigma_nu ds` and `int sigma_1tau ds` over `Gamma_C` (the x-range of body one's
/// domain) by a composite 6-point Gauss rule on 512 pieces: for contact
/// solutions that give no closed form.
pub fn integrated_resultants(exact: &dyn ExactContact) -> Resultants {
    let domain = exact.domain(crate::exact::BodyId::One);
    let (a, b) = (domain.min.x, domain.max.x);
    let rule = GaussLegendre::try_new(GaussLegendre::MAX_POINTS).expect("the largest rule exists");
    let width = (b - a) / RESULTANT_INTERVALS as f64;
    let mut resultants = Resultants {
        normal: 0.0,
        tangential: 0.0,
    };
    for k in 0..RESULTANT_INTERVALS {
        let start = a + k as f64 * width;
        for (t, w) in rule.nodes().iter().zip(rule.weights()) {
            let x = start + 0.5 * width * (1.0 + t);
            let values = exact.interface_values(x);
            resultants.normal += 0.5 * width * w * values.sigma_nu;
            resultants.tangential += 0.5 * width * w * values.sigma_1tau;
        }
    }
    resultants
}
