//! The beam element (`softway::element::beam`) on supports against exact frequencies:
//! simply supported Euler-Bernoulli and Timoshenko beams (observed order of the first three
//! frequencies on a ladder of meshes, no shear locking at L/h = 1000), a beam on many stiff
//! supports (its pinned-pinned frequency and the band of the bays' first modes), and a
//! ring of UIC60 rail on pads (and on pads, half-sleepers and ballast) against the Floquet
//! dispersion relation of the beam on periodic supports.

use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Mat, Par, Side};
use softway::assembly::{Assembler, DofLayout, ElementFamily};
use softway::element::beam::{self, Beam2, BeamMatrix, BeamSection, BeamTheory, Frame2};
use softway::element::discrete::{Discrete, Link, PointMass, SpringDamper, SpringKind};
use std::f64::consts::PI;

/// The `count` lowest `omega` (rad/s) of `K phi = omega^2 M phi` on the free dofs (dense:
/// Cholesky of `M`, `L^-1 K L^-T` scaled to unit max-norm, self-adjoint eigensolver).
fn frequencies(asm: &Assembler, m: &[f64], k: &[f64], fixed: &[usize], count: usize) -> Vec<f64> {
    let n = asm.pattern.nrows();
    let free: Vec<usize> = (0..n).filter(|d| !fixed.contains(d)).collect();
    let (md, kd) = (asm.to_dense(m), asm.to_dense(k));
    let nf = free.len();
    let pick = |a: &Mat<f64>| Mat::<f64>::from_fn(nf, nf, |i, j| a[(free[i], free[j])]);
    let (mf, mut kf) = (pick(&md), pick(&kd));
    let l = mf
        .llt(Side::Lower)
        .expect("mass positive definite")
        .L()
        .to_owned();
    solve_lower_triangular_in_place(l.as_ref(), kf.as_mut(), Par::Seq);
    let mut b = kf.transpose().to_owned();
    solve_lower_triangular_in_place(l.as_ref(), b.as_mut(), Par::Seq);
    let scale = (0..nf)
        .flat_map(|i| (0..nf).map(move |j| (i, j)))
        .fold(0.0f64, |s, (i, j)| s.max(b[(i, j)].abs()));
    let sym = Mat::<f64>::from_fn(nf, nf, |i, j| 0.5 * (b[(i, j)] + b[(j, i)]) / scale);
    let evd = sym.self_adjoint_eigen(Side::Lower).expect("eigensolver");
    let mut w: Vec<f64> = (0..nf)
        .map(|i| (scale * evd.S().column_vector()[i]).max(0.0).sqrt())
        .collect();
    w.sort_by(f64::total_cmp);
    w.truncate(count);
    w
}

/// A beam of `(w, theta)` nodes: the layout, the element family and the lengths.
struct Line {
    layout: DofLayout,
    family: ElementFamily,
    lengths: Vec<f64>,
}

/// `n_el` equal elements over `[0, length]`; with `ring`, the last element joins the last
/// node to node 0 (a closed track of the same length: periodic boundary conditions).
fn line(length: f64, n_el: usize, ring: bool) -> Line {
    let n_nodes = if ring { n_el } else { n_el + 1 };
    let layout = DofLayout::uniform(n_nodes, 2);
    let coords: Vec<f64> = (0..=n_el)
        .flat_map(|i| [length * i as f64 / n_el as f64, 0.0])
        .collect();
    let conn: Vec<[usize; 2]> = (0..n_el).map(|e| [e, e + 1]).collect();
    let lengths = beam::lengths(&coords, 2, &conn).unwrap();
    let conn: Vec<[usize; 2]> = conn.iter().map(|&[a, b]| [a, b % n_nodes]).collect();
    let family = ElementFamily::on_nodes(&layout, &conn).unwrap();
    Line {
        layout,
        family,
        lengths,
    }
}

/// `M` and `K` of the beam (family 0) plus the discrete elements (families 1, 2) on `asm`.
fn beam_matrices(
    asm: &Assembler,
    line: &Line,
    section: &BeamSection,
    theory: BeamTheory,
    discrete: &Discrete,
) -> (Vec<f64>, Vec<f64>) {
    let op = |matrix| Beam2 {
        lengths: &line.lengths,
        section,
        theory,
        matrix,
    };
    let m = asm.assemble(&op(BeamMatrix::Mass));
    let mut k = asm.assemble(&op(BeamMatrix::Stiffness));
    let mut mm = m.clone();
    let mut c = asm.zeros();
    discrete
        .add_matrices_into(asm, 1, &mut mm, &mut c, &mut k)
        .unwrap();
    (mm, k)
}

fn assembler(line: &Line, discrete: &Discrete, extra_dofs: usize) -> Assembler {
    let mut fams = vec![line.family.clone()];
    fams.extend(discrete.families());
    Assembler::try_with_families(line.layout.n_dofs() + extra_dofs, fams).unwrap()
}

/// The simply supported beam's first `count` frequencies (rad/s) with `n_el` elements.
fn simply_supported(
    s: &BeamSection,
    theory: BeamTheory,
    length: f64,
    n_el: usize,
    count: usize,
) -> Vec<f64> {
    let l = line(length, n_el, false);
    let d = Discrete::new();
    let asm = assembler(&l, &d, 0);
    let (m, k) = beam_matrices(&asm, &l, s, theory, &d);
    let fixed = [l.layout.dof(0, 0).unwrap(), l.layout.dof(n_el, 0).unwrap()];
    frequencies(&asm, &m, &k, &fixed, count)
}

/// Exact pinned-pinned frequency (rad/s) of the mode of wavenumber `k = n pi / L` (1/m).
/// Euler-Bernoulli: `omega = k^2 sqrt(EI / rho A)`. Timoshenko: with `w = sin(k x) e^{i omega t}`
/// Timoshenko's equation
/// `EI w'''' + rho A w'' - rho I (1 + E / (kappa G)) w''''_{xxtt} + rho^2 I / (kappa G) w_{tttt} = 0`
/// gives `a omega^4 - b omega^2 + c = 0`, `a = rho^2 I / (kappa G)`,
/// `b = rho A + rho I k^2 (1 + E / (kappa G))`, `c = EI k^4`; the lower root is the
/// flexural branch.
fn exact_pinned(s: &BeamSection, theory: BeamTheory, k: f64) -> f64 {
    match theory {
        BeamTheory::EulerBernoulli => k * k * (s.ei() / s.rho_a()).sqrt(),
        BeamTheory::Timoshenko => {
            let kg = s.shear_coefficient * s.shear_modulus;
            let a = s.density * s.density * s.inertia / kg;
            let b = s.rho_a() + s.density * s.inertia * k * k * (1.0 + s.young / kg);
            let c = s.ei() * k.powi(4);
            // Lower root, written without cancellation: 2c / (b + sqrt(b^2 - 4ac)).
            (2.0 * c / (b + (b * b - 4.0 * a * c).sqrt())).sqrt()
        }
    }
}

/// `[1.234e-5, ...]` for a printed ladder.
fn sci(v: &[f64]) -> String {
    let s: Vec<String> = v.iter().map(|x| format!("{x:.3e}")).collect();
    format!("[{}]", s.join(", "))
}

/// Observed orders of a ladder of errors on meshes halved each time.
fn orders(errs: &[f64]) -> Vec<f64> {
    errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

fn ladder_orders(s: &BeamSection, theory: BeamTheory, length: f64) -> Vec<Vec<f64>> {
    let ladder = [4, 8, 16, 32];
    let exact: Vec<f64> = (1..=3)
        .map(|n| exact_pinned(s, theory, n as f64 * PI / length))
        .collect();
    let mut errs = vec![Vec::new(); 3];
    for &ne in &ladder {
        let w = simply_supported(s, theory, length, ne, 3);
        for n in 0..3 {
            errs[n].push((w[n] - exact[n]) / exact[n]);
        }
    }
    println!("{theory:?} L = {length}: exact omega {exact:.6?}");
    for (n, e) in errs.iter().enumerate() {
        println!("  mode {}: relative errors {}", n + 1, sci(e));
        // Consistent mass: the frequencies are upper bounds (Rayleigh-Ritz).
        assert!(e.iter().all(|&x| x > 0.0), "mode {}: {e:?}", n + 1);
    }
    errs.iter().map(|e| orders(e)).collect()
}

#[test]
fn simply_supported_euler_bernoulli_converges_at_fourth_order() {
    let s = BeamSection::UIC60;
    let o = ladder_orders(&s, BeamTheory::EulerBernoulli, 6.0);
    println!("  orders {o:.3?}");
    for (n, on) in o.iter().enumerate() {
        for &x in on {
            assert!(x > 3.5 && x < 4.5, "mode {}: order {x}", n + 1);
        }
    }
}

#[test]
fn simply_supported_stocky_timoshenko_converges_at_second_order() {
    // The interdependent interpolation element has a constant shear strain per element:
    // where the shear energy matters (L / h = 5) its frequencies converge at second order
    // (the Hermite element's fourth order is the slender limit, Phi -> 0).
    // L / h = 5: a steel bar 1 m long, 0.2 m deep.
    let s = BeamSection::rectangle(2.1e11, 0.3, 7850.0, 0.05, 0.2);
    let length = 1.0;
    for n in 1..=3 {
        let k = n as f64 * PI / length;
        let (eb, ti) = (
            exact_pinned(&s, BeamTheory::EulerBernoulli, k),
            exact_pinned(&s, BeamTheory::Timoshenko, k),
        );
        println!(
            "mode {n}: EB {eb:.2} rad/s, Timoshenko {ti:.2} rad/s, ratio {:.4}",
            ti / eb
        );
        assert!(
            ti < 0.95 * eb,
            "shear and rotary inertia lower mode {n} by > 5%"
        );
    }
    let o = ladder_orders(&s, BeamTheory::Timoshenko, length);
    println!("  orders {o:.3?}");
    for (n, on) in o.iter().enumerate() {
        for &x in on {
            assert!(x > 1.9 && x < 2.2, "mode {}: order {x}", n + 1);
        }
    }
}

#[test]
fn slender_timoshenko_beam_tends_to_euler_bernoulli_without_locking() {
    // L / h = 1000 with 4 elements: the Timoshenko element is the Hermite one as Phi -> 0.
    let length = 1.0;
    let s = BeamSection::rectangle(2.1e11, 0.3, 7850.0, 0.01, 1.0e-3);
    let eb_exact = exact_pinned(&s, BeamTheory::EulerBernoulli, PI / length);
    let ti = simply_supported(&s, BeamTheory::Timoshenko, length, 4, 1)[0];
    let eb = simply_supported(&s, BeamTheory::EulerBernoulli, length, 4, 1)[0];
    let (rel, rel_fe) = ((ti - eb_exact) / eb_exact, (ti - eb) / eb);
    println!("L/h = 1000, 4 elements: Timoshenko {ti:.6} vs EB exact {eb_exact:.6} ({rel:.2e}), vs EB element {rel_fe:.2e}");
    assert!(rel.abs() < 1e-3);
    assert!(
        rel_fe.abs() < 1e-5,
        "no locking: the elements agree to the shear correction"
    );
    // Across slenderness the Timoshenko element follows the exact Timoshenko value, and
    // the exact value tends to Euler-Bernoulli.
    for slender in [5.0, 20.0, 100.0, 1000.0] {
        let h = length / slender;
        let s = BeamSection::rectangle(2.1e11, 0.3, 7850.0, 0.01, h);
        let exact = exact_pinned(&s, BeamTheory::Timoshenko, PI / length);
        let eb = exact_pinned(&s, BeamTheory::EulerBernoulli, PI / length);
        let fe = simply_supported(&s, BeamTheory::Timoshenko, length, 32, 1)[0];
        println!(
            "L/h = {slender}: FE / exact - 1 = {:.2e}, Timoshenko / EB - 1 = {:.2e}",
            fe / exact - 1.0,
            exact / eb - 1.0
        );
        assert!((fe / exact - 1.0).abs() < 1e-4);
    }
}

/// The track data of the next issue: sleeper spacing, pad, half-sleeper, ballast.
const BAY: f64 = 0.6;
const PAD_K: f64 = 200.0e6;
const SLEEPER_M: f64 = 177.5;
const BALLAST_K: f64 = 40.0e6;

/// The supports of a track: pads on rigid ground, or pad - half-sleeper - ballast.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Support {
    /// A spring of this stiffness (N/m) to the ground.
    Spring(f64),
    /// Pad, sleeper mass and ballast in series.
    PadSleeperBallast,
}

impl Support {
    /// The dynamic stiffness of the support at `omega` as a fraction `(num, den)`:
    /// `k` alone, or `k_p (k_b - m omega^2) / (k_p + k_b - m omega^2)` (the sleeper's
    /// equation eliminated).
    fn stiffness(self, omega: f64) -> (f64, f64) {
        match self {
            Support::Spring(k) => (k, 1.0),
            Support::PadSleeperBallast => {
                let d = BALLAST_K - SLEEPER_M * omega * omega;
                (PAD_K * d, PAD_K + d)
            }
        }
    }
}

/// A beam of `bays` bays of `ne` elements with a support at the first node of every bay;
/// `ring`: closed (periodic). Returns `M`, `K`, the assembler and the fixed dofs (the two
/// end deflections of an open beam, pinned).
fn supported_beam(
    s: &BeamSection,
    theory: BeamTheory,
    bays: usize,
    ne: usize,
    support: Support,
    ring: bool,
) -> (Assembler, Vec<f64>, Vec<f64>, Vec<usize>) {
    let mut l = line(bays as f64 * BAY, bays * ne, ring);
    let mut d = Discrete::new();
    let first_support = if ring { 0 } else { 1 };
    for b in first_support..bays {
        let w = l.layout.dof(b * ne, 0).unwrap();
        let spring = |link, k| SpringDamper {
            link,
            kind: SpringKind::Translational,
            stiffness: k,
            damping: 0.0,
        };
        match support {
            Support::Spring(k) => d.add_spring(spring(Link::Ground(w), k)).unwrap(),
            Support::PadSleeperBallast => {
                let node = l.layout.push_nodes(1, 1).start;
                let y = l.layout.dof(node, 0).unwrap();
                d.add_spring(spring(Link::Between(w, y), PAD_K)).unwrap();
                d.add_mass(PointMass {
                    dof: y,
                    mass: SLEEPER_M,
                })
                .unwrap();
                d.add_spring(spring(Link::Ground(y), BALLAST_K)).unwrap();
            }
        }
    }
    let asm = assembler(&l, &d, 0);
    let (m, k) = beam_matrices(&asm, &l, s, theory, &d);
    let fixed = if ring {
        vec![]
    } else {
        vec![0, l.layout.dof(bays * ne, 0).unwrap()]
    };
    (asm, m, k, fixed)
}

fn ring_frequencies(theory: BeamTheory, ne: usize, support: Support, count: usize) -> Vec<f64> {
    let (asm, m, k, fixed) = supported_beam(&BeamSection::UIC60, theory, 10, ne, support, true);
    frequencies(&asm, &m, &k, &fixed, count)
}

#[test]
fn beam_on_stiff_periodic_supports_has_the_bay_pinned_pinned_frequency() {
    // Ten bays of UIC60 (Euler-Bernoulli), ends pinned, nine supports of 1e12 N/m (700
    // times the bay's own 48 EI / L^3): the lowest mode is the bays' pinned-pinned mode
    // sin(pi x / L_b), exactly the element's simply supported bay, at
    // (pi / L_b)^2 sqrt(EI / rho A); it is the bottom of a band of ten modes that ends
    // below the clamped-clamped bay, (4.730041 / L_b)^2 sqrt(EI / rho A).
    let s = BeamSection::UIC60;
    let theory = BeamTheory::EulerBernoulli;
    let exact_pp = exact_pinned(&s, theory, PI / BAY);
    let exact_cc = (4.730_040_744_862_704f64 / BAY).powi(2) * (s.ei() / s.rho_a()).sqrt();
    let mut errs = Vec::new();
    for ne in [2, 4, 8, 16] {
        let (asm, m, k, fixed) = supported_beam(&s, theory, 10, ne, Support::Spring(1e12), false);
        let w = frequencies(&asm, &m, &k, &fixed, 11);
        let bay = simply_supported(&s, theory, BAY, ne, 1)[0];
        println!(
            "{ne} elements per bay: lowest {:.3} Hz, bay {:.3} Hz, band top {:.3} Hz, next {:.3} Hz (exact pp {:.3}, cc {:.3})",
            w[0] / (2.0 * PI),
            bay / (2.0 * PI),
            w[9] / (2.0 * PI),
            w[10] / (2.0 * PI),
            exact_pp / (2.0 * PI),
            exact_cc / (2.0 * PI)
        );
        assert!((w[0] - bay).abs() < 1e-9 * bay, "the pinned-pinned mode");
        assert!(
            w[9] < exact_cc * 1.001 && w[10] > exact_cc,
            "a band of ten modes"
        );
        errs.push((w[0] - exact_pp) / exact_pp);
    }
    let o = orders(&errs);
    println!("pinned-pinned errors {}, orders {o:.3?}", sci(&errs));
    assert!(o.iter().all(|&x| x > 3.5));
    assert!(errs[3] < 2e-6);
}

/// `(mu^2 - 2 - t1 mu + t2) den` for the Euler-Bernoulli beam on supports of dynamic
/// stiffness `num / den` every `BAY`, at `omega` and `mu = 2 cos(q L_b)`: zero at the
/// Floquet (Bloch) frequencies of wavenumber `q`.
///
/// One bay's transfer matrix `P = S T` maps `y = (w, w'/beta, w''/beta^2, w'''/beta^3)`
/// across a support (`S`: `EI [w'''] = -k w`) and a bay (`T`, the Krylov functions of
/// `beta L_b`, `beta^4 = rho A omega^2 / EI`). `P` is reciprocal (`det P = 1`, eigenvalues in
/// pairs `lambda, 1 / lambda`), so `det(P - lambda I) = 0` with `lambda = e^{i q L_b}` is
/// `mu^2 - t1 mu + t2 - 2 = 0`, `t1 = tr P`, `t2` the sum of `P`'s principal 2x2 minors.
fn dispersion(s: &BeamSection, omega: f64, mu: f64, support: Support) -> f64 {
    let beta = (s.rho_a() * omega * omega / s.ei()).powf(0.25);
    let z = beta * BAY;
    let (ch, sh, c, sn) = (z.cosh(), z.sinh(), z.cos(), z.sin());
    let k = [
        0.5 * (ch + c),
        0.5 * (sh + sn),
        0.5 * (ch - c),
        0.5 * (sh - sn),
    ];
    // T[i][j] = k[(j - i) mod 4].
    let t = |i: usize, j: usize| k[(j + 4 - i) % 4];
    let (num, den) = support.stiffness(omega);
    // P = T - kappa e4 (e1^T T), kappa = k / (EI beta^3); t1 and t2 (hence f) are linear in
    // kappa (only row 4 depends on it), so with k = num / den, f den = f(0) den + f'(0) num
    // (EI beta^3)^-1 has no pole where den vanishes (the sleeper on its ballast alone).
    let f = |kappa: f64| {
        let p = |i: usize, j: usize| t(i, j) - if i == 3 { kappa * t(0, j) } else { 0.0 };
        let t1: f64 = (0..4).map(|i| p(i, i)).sum();
        let mut t2 = 0.0;
        for i in 0..4 {
            for j in i + 1..4 {
                t2 += p(i, i) * p(j, j) - p(i, j) * p(j, i);
            }
        }
        mu * mu - 2.0 - mu * t1 + t2
    };
    let (f0, f1) = (f(0.0), f(1.0));
    f0 * den + (f1 - f0) * num / (s.ei() * beta.powi(3))
}

/// The Floquet frequencies (rad/s) below `omega_max` of a ring of `bays` bays: the roots of
/// [`dispersion`] at the ring's wavenumbers `q_j = 2 pi j / (bays L_b)`, each twice but for
/// `j = 0` and `j = bays / 2` (a scan of 20,000 points, then bisection).
fn floquet_frequencies(s: &BeamSection, bays: usize, support: Support, omega_max: f64) -> Vec<f64> {
    let mut roots = Vec::new();
    for j in 0..=bays / 2 {
        let mu = 2.0 * (2.0 * PI * j as f64 / bays as f64).cos();
        let times = if j == 0 || 2 * j == bays { 1 } else { 2 };
        let f = |w: f64| dispersion(s, w, mu, support);
        let n = 20_000;
        let grid = |i: usize| omega_max * i as f64 / n as f64;
        for i in 1..n {
            let (mut a, mut b) = (grid(i), grid(i + 1));
            if f(a).signum() == f(b).signum() {
                continue;
            }
            for _ in 0..200 {
                let c = 0.5 * (a + b);
                if f(c).signum() == f(a).signum() {
                    a = c;
                } else {
                    b = c;
                }
            }
            roots.extend(std::iter::repeat_n(0.5 * (a + b), times));
        }
    }
    roots.sort_by(f64::total_cmp);
    roots
}

#[test]
fn uic60_ring_on_pads_matches_the_floquet_dispersion_relation() {
    // A closed track of ten 0.6 m bays of UIC60 (Euler-Bernoulli) on 200 MN/m pads (rigid
    // sleepers), and on pad - 177.5 kg half-sleeper - 40 MN/m ballast (undamped): every
    // frequency below 2 kHz against the dispersion relation of the infinite periodic track
    // at the ring's wavenumbers.
    let s = BeamSection::UIC60;
    let omega_max = 2.0 * PI * 2000.0;
    for support in [Support::Spring(PAD_K), Support::PadSleeperBallast] {
        let exact = floquet_frequencies(&s, 10, support, omega_max);
        let mut worst = Vec::new();
        for ne in [4, 8, 16] {
            let fe = ring_frequencies(BeamTheory::EulerBernoulli, ne, support, exact.len());
            let rel: Vec<f64> = fe.iter().zip(&exact).map(|(a, b)| (a - b) / b).collect();
            let w = rel.iter().fold(0.0f64, |m, r| m.max(r.abs()));
            println!(
                "{support:?}, {ne} elements per bay: {} frequencies below 2 kHz, worst relative error {w:.2e}",
                exact.len()
            );
            worst.push(w);
        }
        let hz: Vec<f64> = exact.iter().map(|w| w / (2.0 * PI)).collect();
        println!("  Floquet frequencies, Hz: {hz:.1?}");
        let o = orders(&worst);
        println!("  orders {o:.3?}");
        assert!(worst[2] < 1e-5, "{worst:?}");
        assert!(o.iter().all(|&x| x > 3.5), "{o:?}");
    }
}

#[test]
fn uic60_pinned_pinned_frequency_euler_bernoulli_and_timoshenko() {
    // The pinned-pinned mode of a track (nodes at the supports, wavelength 2 L_b) does not
    // load the supports: its frequency is the 0.6 m bay's, whatever the pads. The ring of
    // ten bays on pads holds it exactly as the simply supported bay of the same elements,
    // and it converges to (pi / L_b)^2 sqrt(EI / rho A) (Euler-Bernoulli) or the root of
    // Timoshenko's equation at k = pi / L_b.
    let s = BeamSection::UIC60;
    for theory in [BeamTheory::EulerBernoulli, BeamTheory::Timoshenko] {
        let exact = exact_pinned(&s, theory, PI / BAY);
        let mut errs = Vec::new();
        for ne in [4, 8, 16, 32] {
            let bay = simply_supported(&s, theory, BAY, ne, 1)[0];
            let ring = ring_frequencies(theory, ne, Support::Spring(PAD_K), 30);
            let nearest = ring.iter().fold(f64::INFINITY, |m, &w| {
                if (w - bay).abs() < (m - bay).abs() {
                    w
                } else {
                    m
                }
            });
            assert!(
                (nearest - bay).abs() < 1e-8 * bay,
                "{theory:?} {ne}: {nearest} vs {bay}"
            );
            errs.push((bay - exact) / exact);
        }
        let o = orders(&errs);
        println!(
            "UIC60 {theory:?}: pinned-pinned {:.2} Hz exact, errors {}, orders {o:.3?}",
            exact / (2.0 * PI),
            sci(&errs)
        );
        // Fourth order for Euler-Bernoulli; second for Timoshenko (constant shear strain per
        // element; the rail's 0.6 m bay is only 3.5 rail heights long).
        let order = if theory == BeamTheory::EulerBernoulli {
            3.5
        } else {
            1.9
        };
        assert!(o.iter().all(|&x| x > order), "{o:?}");
        let tol = if theory == BeamTheory::EulerBernoulli {
            1e-6
        } else {
            2e-4
        };
        assert!(errs[3].abs() < tol, "{errs:?}");
    }
    let (eb, ti) = (
        exact_pinned(&s, BeamTheory::EulerBernoulli, PI / BAY) / (2.0 * PI),
        exact_pinned(&s, BeamTheory::Timoshenko, PI / BAY) / (2.0 * PI),
    );
    assert!(
        (950.0..1100.0).contains(&ti) && eb > 1.3 * ti,
        "EB {eb} Hz, Timoshenko {ti} Hz"
    );
}

#[test]
fn inclined_frame_has_the_bending_beam_frequencies_and_the_bar_frequencies() {
    // A simply supported 6 m UIC60 span (Timoshenko) along a 30 degree incline, 16 frame elements
    // (u_x, u_y, theta per node), both ends held in x and y: bending and stretching decouple
    // for a straight beam in any direction, so its spectrum is the bending-only element's
    // plus the axial bar's (linear elements, consistent mass: the fixed-fixed bar's
    // discrete frequencies `omega_n^2 = (6 / l^2)(c^2)(1 - cos t_n)/(2 + cos t_n)`,
    // `t_n = n pi / N`, `c^2 = E / rho`).
    let s = BeamSection::UIC60;
    let (length, n_el) = (6.0, 16);
    let dir = [30f64.to_radians().cos(), 30f64.to_radians().sin()];
    let layout = DofLayout::uniform(n_el + 1, 3);
    let conn: Vec<[usize; 2]> = (0..n_el).map(|e| [e, e + 1]).collect();
    let ends: Vec<[[f64; 2]; 2]> = conn
        .iter()
        .map(|&[a, b]| {
            let p = |i: usize| {
                let x = length * i as f64 / n_el as f64;
                [1.0 + x * dir[0], -2.0 + x * dir[1]]
            };
            [p(a), p(b)]
        })
        .collect();
    let asm = Assembler::try_with_families(
        layout.n_dofs(),
        vec![ElementFamily::on_nodes(&layout, &conn).unwrap()],
    )
    .unwrap();
    let op = |matrix| Frame2 {
        ends: &ends,
        section: &s,
        theory: BeamTheory::Timoshenko,
        matrix,
    };
    let (m, k) = (
        asm.assemble(&op(BeamMatrix::Mass)),
        asm.assemble(&op(BeamMatrix::Stiffness)),
    );
    let fixed: Vec<usize> = [0, n_el]
        .iter()
        .flat_map(|&n| [layout.dof(n, 0).unwrap(), layout.dof(n, 1).unwrap()])
        .collect();
    // Every mode: 3 (N + 1) - 4 frame dofs, 2 (N + 1) - 2 bending and N - 1 axial.
    let frame = frequencies(&asm, &m, &k, &fixed, usize::MAX);
    let bending = simply_supported(&s, BeamTheory::Timoshenko, length, n_el, usize::MAX);
    let l = length / n_el as f64;
    let c2 = s.young / s.density;
    let mut expected: Vec<f64> = (1..n_el)
        .map(|n| {
            let t = (n as f64 * PI / n_el as f64).cos();
            (6.0 / (l * l) * c2 * (1.0 - t) / (2.0 + t)).sqrt()
        })
        .chain(bending)
        .collect();
    expected.sort_by(f64::total_cmp);
    assert_eq!(
        (frame.len(), expected.len()),
        (3 * (n_el + 1) - 4, 3 * (n_el + 1) - 4)
    );
    for (a, b) in frame.iter().zip(&expected) {
        assert!((a - b).abs() < 1e-7 * b, "{a} vs {b}");
    }
}
