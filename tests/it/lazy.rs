//! Issue 6: the lazy component walk equals the exhaustive sweep's component.

use caymos::analysis::{LAZY_ABOVE_STEPS, Scope, Solved, analyse, analyse_with};
use caymos::bundled;
use caymos::cayley_space::CayleySpace;
use caymos::generate::{chain, hard_cases, random_linkage, strandbeest, to_toml};
use caymos::lazy::{LazyOptions, component_through};
use caymos::motion::{Component, components};
use caymos::real::Jet;
use caymos::realize::Realization;
use caymos::scene::Scene;
use proptest::prelude::*;

/// A component as (type, λ of the end walked from, λ of the end walked to) in traversal order.
fn walk(space: &CayleySpace<f64>, c: &Component) -> Vec<(String, f64, f64)> {
    c.intervals
        .iter()
        .zip(&c.forward)
        .map(|(&i, &fwd)| {
            let iv = &space.intervals[i];
            let (a, b) = if fwd { (iv.lower.lambda, iv.upper.lambda) } else { (iv.upper.lambda, iv.lower.lambda) };
            (iv.ty.to_string(), a, b)
        })
        .collect()
}

/// Equal as cycles: same length, and some rotation matches type by type with
/// endpoints within `tol`.
fn same_cycle(lazy: &[(String, f64, f64)], full: &[(String, f64, f64)], tol: f64) -> Result<(), String> {
    if lazy.len() != full.len() {
        return Err(format!("lazy has {} intervals, exhaustive {}:\n{lazy:?}\n{full:?}", lazy.len(), full.len()));
    }
    let m = full.len();
    let close = |x: f64, y: f64| (x - y).abs() <= tol;
    let matches = |r: usize| {
        (0..m).all(|t| {
            let (a, b) = (&lazy[t], &full[(t + r) % m]);
            a.0 == b.0 && close(a.1, b.1) && close(a.2, b.2)
        })
    };
    if (0..m).any(matches) { Ok(()) } else { Err(format!("no rotation matches:\nlazy {lazy:?}\nfull {full:?}")) }
}

/// For every component of the exhaustive analysis, start the lazy walk
/// inside its first interval and compare.
fn check_scene(scene: Scene) -> Result<usize, String> {
    check_scene_on(scene, None)
}

/// [`check_scene`] on a given base (`None`: the scene's own, or the chosen one).
fn check_scene_on(scene: Scene, base: Option<[usize; 2]>) -> Result<usize, String> {
    let name = format!("{} on base {base:?}", scene.name);
    let a = analyse_with(scene, base, Scope::Full).map_err(|e| e.to_string())?;
    let s: Solved = a.outcome.map_err(|_| format!("{name}: outside the class"))?;
    let jet = s.construction.convert::<Jet<f64>>();
    let tol = 1e-9 * a.linkage.scale;
    // One walk, and two walks at once from the start's two ends (forced on
    // scenes of any size: by default only long chains go both ways).
    let ways =
        [usize::MAX, 0].map(|both_ways_from_steps| LazyOptions { both_ways_from_steps, ..LazyOptions::default() });
    for ((k, c), options) in s.components.list.iter().enumerate().flat_map(|c| ways.map(|w| (c, w))) {
        let name = format!("{name}, both ways from {} steps", options.both_ways_from_steps);
        let first = &s.space.intervals[c.intervals[0]];
        let start = 0.5 * (first.lower.lambda + first.upper.lambda);
        let lazy = component_through(&s.construction, &s.certifier, &jet, &first.ty, start, options)
            .map_err(|e| format!("{name}: component {k}: start not realizable: {e:?}"))?;
        let lazy_components = components(&lazy);
        if lazy_components.list.len() != 1 {
            return Err(format!("{name}: component {k}: lazy space splits into {}", lazy_components.list.len()));
        }
        let lc = &lazy_components.list[0];
        if lc.closed != c.closed {
            return Err(format!("{name}: component {k}: closed {} vs {}", lc.closed, c.closed));
        }
        same_cycle(&walk(&lazy, lc), &walk(&s.space, c), tol).map_err(|e| format!("{name}: component {k}: {e}"))?;
    }
    Ok(s.components.list.len())
}

#[test]
fn lazy_equals_exhaustive_on_every_bundled_scene() {
    let mut checked = 0;
    for b in bundled::BUNDLED {
        let scene = bundled::load(b.name).unwrap();
        let a = analyse(scene.clone(), None).unwrap();
        if a.outcome.is_err() {
            continue; // not 1-dof tree-decomposable: nothing to walk
        }
        checked += check_scene(scene).unwrap_or_else(|e| panic!("{e}"));
    }
    assert!(checked >= 20, "expected components in the bundled scenes, walked {checked}");
}

/// The exact tangency on bases v1–v2 and p–q: both steps are flat at the
/// one realization (λ = 7). A walk started there returns the point in all
/// four types, as the exhaustive sweep does; before, it stopped at the
/// first flat step and returned one type.
#[test]
fn a_lazy_start_where_several_steps_are_flat_at_an_isolated_point_takes_every_flip() {
    let scene = caymos::generate::tangency();
    let a = analyse(scene.clone(), None).unwrap();
    let id = |n: &str| a.linkage.names.iter().position(|x| x == n).unwrap();
    for base in [["v1", "v2"], ["p", "q"]] {
        let a = analyse_with(scene.clone(), Some([id(base[0]), id(base[1])]), Scope::Full).unwrap();
        let s: Solved = a.outcome.unwrap();
        let jet = s.construction.convert::<Jet<f64>>();
        let start = &s.space.intervals[0];
        assert_eq!(start.lower.lambda, 7.0, "base {base:?}");
        let lazy = component_through(&s.construction, &s.certifier, &jet, &start.ty, 7.0, LazyOptions::default())
            .unwrap_or_else(|e| panic!("base {base:?}: {e:?}"));
        let points = |space: &CayleySpace<f64>| {
            let mut p: Vec<(String, f64, f64, usize)> = space
                .intervals
                .iter()
                .map(|i| (i.ty.to_string(), i.lower.lambda, i.upper.lambda, i.lower.events.len()))
                .collect();
            p.sort_by(|x, y| x.0.cmp(&y.0));
            p
        };
        assert_eq!(points(&lazy), points(&s.space), "base {base:?}");
        assert_eq!(points(&lazy).len(), 4, "base {base:?}");
        assert_eq!(components(&lazy).connected_set_count(), 1, "base {base:?}");
    }
}

/// The Peaucellier inversor on bases O–C, O–P, C–P and B–D. On O–P its
/// rhombus C ◁ (B, D) touches stretched at λ = 4, where A ◁ (O, C) touches
/// stretched too; beside the touch C is known to about √ε in f64, so the
/// next slack read 0 at λ = 4.0000000029 and the walk took it for an end
/// (two components, the drawn one [4, 8], where the sweep has one interval
/// [2, 8]). The walk now asks the certifier there. On B–D three steps are
/// flat at once at λ = 6: the walk entered ---- there, read no slope for
/// the step it entered by (a square root's), and returned a point where the
/// sweep has [0, 6]. On A–B and A–D, step 3 touches folded at λ = √19,
/// where the kite O, B, C, D folds flat, and beyond it the rhombus
/// P ◁ (B, D) degenerates in the type walked so far: both now end the
/// interval there (the sweep dropped ++-+ whole, the walk crossed the
/// degenerate part).
#[test]
fn lazy_equals_exhaustive_on_peaucellier_bases_through_the_touch() {
    let scene = bundled::load("peaucellier").unwrap();
    let a = analyse(scene.clone(), None).unwrap();
    let id = |n: &str| a.linkage.names.iter().position(|x| x == n).unwrap();
    for [u, w] in [["O", "C"], ["O", "P"], ["C", "P"], ["B", "D"], ["A", "B"], ["A", "D"]] {
        check_scene_on(scene.clone(), Some([id(u), id(w)])).unwrap_or_else(|e| panic!("{u}–{w}: {e}"));
    }
}

/// Peaucellier on bases A–B and A–D: in some types D lands on B (the
/// triangle O, C, D is the triangle O, C, B), so the rhombus P ◁ (B, D) has
/// its base joints coincide and P turns freely. Which types those are
/// changes at λ = √19, where B crosses the line OC (step 3 touches folded:
/// the kite O, B, C, D is flat). No interval, full or lazy, may be
/// degenerate inside: the walk used to go through -+-+ on A–B (coincident
/// all along) and across ++-+ below √19, and the sweep dropped ++-+ whole
/// (its valid part is [√19, 5]). The full analysis has ++-+ on exactly
/// [√19, 5] and ++++ on [3, √19], and 4 components in 1 connected set:
/// the kite's flat touch at √19 joins 1 with 3 and 2 with 4, and at
/// λ = √13 (|OC| = 4, where the inversor puts P on C) step 4 touches
/// stretched inside -++- and +---, whose P-flipped types meet them there.
#[test]
fn no_peaucellier_interval_is_degenerate_inside_on_bases_a_b_and_a_d() {
    use caymos::certify::Closes;
    let scene = bundled::load("peaucellier").unwrap();
    let a = analyse(scene.clone(), None).unwrap();
    let id = |n: &str| a.linkage.names.iter().position(|x| x == n).unwrap();
    let root19 = 19f64.sqrt();
    for [u, w] in [["A", "B"], ["A", "D"]] {
        for scope in [Scope::Full, Scope::Lazy] {
            let s = analyse_with(scene.clone(), Some([id(u), id(w)]), scope).unwrap().outcome.unwrap();
            let degenerate_at = |ty: &caymos::realize::RealizationType, l: f64| {
                (0..ty.0.len()).any(|k| s.certifier.closes(None, &ty.0, l, k) == Closes::Degenerate)
            };
            for iv in &s.space.intervals {
                let (lo, hi) = (iv.lower.lambda, iv.upper.lambda);
                for t in [0.01, 0.25, 0.5, 0.75, 0.99] {
                    let l = lo + t * (hi - lo);
                    assert!(
                        !degenerate_at(&iv.ty, l),
                        "{u}–{w} {scope:?}: {} over [{lo}, {hi}] degenerate at {l}",
                        iv.ty
                    );
                }
            }
            assert!(s.space.intervals.iter().any(|iv| iv.ty.to_string() == "+--+" || iv.ty.to_string() == "-++-"));
            if scope == Scope::Full {
                let span = |ty: &str| {
                    let iv = s.space.intervals.iter().find(|iv| iv.ty.to_string() == ty).expect(ty);
                    [iv.lower.lambda, iv.upper.lambda]
                };
                let (split, whole) = if u == "A" && w == "B" { ("++-+", "++++") } else { ("--+-", "++++") };
                let [lo, hi] = span(split);
                assert!(
                    (lo - root19).abs() <= 4.0 * f64::EPSILON * root19 && hi == 5.0,
                    "{u}–{w}: {split} [{lo}, {hi}]"
                );
                let [lo, hi] = span(whole);
                assert!(
                    lo == 3.0 && (hi - root19).abs() <= 4.0 * f64::EPSILON * root19,
                    "{u}–{w}: {whole} [{lo}, {hi}]"
                );
                assert_eq!((s.components.list.len(), s.components.connected_set_count()), (4, 1), "{u}–{w}");
            }
        }
    }
}

#[test]
fn lazy_equals_exhaustive_on_hard_cases() {
    for scene in hard_cases() {
        check_scene(scene).unwrap_or_else(|e| panic!("{e}"));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn lazy_equals_exhaustive_on_random_scenes(seed in any::<u64>(), steps in 1usize..7, tri in 0.0f64..0.6) {
        let scene = random_linkage(seed, steps, tri);
        check_scene(scene).map_err(TestCaseError::fail)?;
    }
}

#[test]
fn analyse_goes_lazy_above_2_pow_16_types_and_says_so() {
    for scene in [chain(LAZY_ABOVE_STEPS + 4), strandbeest(12)] {
        let name = scene.name.clone();
        let a = analyse(scene, None).unwrap();
        let s = a.outcome.unwrap();
        assert!(s.dec.steps.len() > LAZY_ABOVE_STEPS, "{name}");
        assert!(s.lazy, "{name}");
        let k = s.drawn_component.expect("the drawn realization lies on its component");
        let c = &s.components.list[k];
        assert!(c.closed, "{name}: the walked component is a closed cycle");
        assert_eq!(s.components.list.len(), 1, "{name}: only the drawn component is computed");
        // Every interval's realizations meet every bar, at both ends and inside.
        for &i in &c.intervals {
            let iv = &s.space.intervals[i];
            for l in [iv.lower.lambda, 0.5 * (iv.lower.lambda + iv.upper.lambda), iv.upper.lambda] {
                let pos =
                    s.construction.realize(l, &iv.ty).unwrap_or_else(|e| panic!("{name}: {} at {l}: {e:?}", iv.ty));
                let r = caymos::realize::bar_residual(&a.linkage, &caymos::realize::points(&pos));
                assert!(r <= 1e-9 * a.linkage.scale, "{name}: residual {r}");
            }
        }
        let r = caymos::report::Report::new(&analyse(strandbeest(2), None).unwrap());
        assert_eq!(r.analysis, caymos::report::AnalysisKind::Full);
    }
}

/// The sweep's estimate in closed form: a four-bar's two steps are on the
/// base with one stretched and one folded candidate each and read no bits:
/// (2 + 1) questions realizing 1 step, then (2 + 1) realizing 2: 9.
/// The Limacon's: 3 + 6 + 2·3·3 (step 3 reads one bit) + 4·9·4 (step 4
/// reads two, eight candidates) = 171.
#[test]
fn sweep_estimate_is_the_closed_form_count() {
    for (name, want) in [("fourbar-crank-rocker", 9.0), ("limacon", 171.0)] {
        let s = analyse(bundled::load(name).unwrap(), None).unwrap().outcome.unwrap();
        assert_eq!(s.sweep_estimate, Some(want), "{name}");
        assert!(!s.lazy, "{name}");
    }
}

/// A generated 11-step chain has 2^11 types, under the step limit, but its
/// closed-form candidates multiply (120 at step 11): `Auto` estimates the
/// sweep above its budget and walks the drawn component instead, and the
/// report says why. A 4-legged Strandbeest (13 steps) stays full.
#[test]
fn auto_goes_lazy_where_the_sweep_is_estimated_above_its_budget() {
    let budget = caymos::tolerance::SWEEP_COST_MAX;
    let a = analyse(chain(11), None).unwrap();
    let s = a.outcome.as_ref().unwrap();
    assert!(s.dec.steps.len() <= LAZY_ABOVE_STEPS);
    let cost = s.sweep_estimate.expect("estimated within the step limit");
    assert!(cost > budget, "{cost}");
    assert!(s.lazy);
    assert_eq!(s.components.list.len(), 1);
    let text = caymos::report::Report::new(&a).to_text_with(false);
    assert!(text.contains("above the budget"), "{text}");
    // A sweep decides once, as `Auto` does for the scene as given.
    assert_eq!(caymos::analysis::auto_scope(&chain(11), None), Scope::Lazy);
    assert_eq!(caymos::analysis::auto_scope(&chain(8), None), Scope::Full);
    let beest = analyse(strandbeest(4), None).unwrap().outcome.unwrap();
    assert!(beest.sweep_estimate.is_some_and(|c| c <= budget) && !beest.lazy);
    // `--all` (Scope::Full) estimates too, for the report, and always sweeps.
    let small = analyse_with(chain(8), None, Scope::Full).unwrap().outcome.unwrap();
    assert!(!small.lazy && small.sweep_estimate.is_some_and(|c| c <= budget));
}

/// `--all` has a bounded cost too: an 18-step chain's sweep is estimated at
/// 9e10 realization steps and a 300-step chain's candidate search is
/// unbounded, so both are refused with the reason, before any sweep.
#[test]
fn the_full_analysis_is_refused_beyond_its_budget() {
    for steps in [18, 300] {
        let err = analyse_with(chain(steps), None, Scope::Full).expect_err("refused");
        assert!(err.message.contains("beyond its budget") && err.message.contains("without --all"), "{err}");
        assert!(analyse(chain(steps), None).unwrap().outcome.unwrap().lazy);
    }
}

#[test]
fn lazy_scope_equals_full_scope_and_include_walks_other_components() {
    for name in ["jansen", "limacon", "fourbar-non-grashof"] {
        let full = analyse_with(bundled::load(name).unwrap(), None, Scope::Full).unwrap().outcome.unwrap();
        let mut lazy = analyse_with(bundled::load(name).unwrap(), None, Scope::Lazy).unwrap().outcome.unwrap();
        assert!(lazy.lazy && !full.lazy);
        assert_eq!(lazy.components.list.len(), 1);
        let (kf, kl) = (full.drawn_component.unwrap(), lazy.drawn_component.unwrap());
        same_cycle(&walk(&lazy.space, &lazy.components.list[kl]), &walk(&full.space, &full.components.list[kf]), 1e-9)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        // Ask for a realization in every other component: each is walked once and matches.
        for (k, c) in full.components.list.iter().enumerate() {
            let iv = &full.space.intervals[c.intervals[0]];
            let r = Realization { ty: iv.ty.clone(), lambda: 0.5 * (iv.lower.lambda + iv.upper.lambda) };
            let i = lazy.include(&r).unwrap_or_else(|| panic!("{name}: component {k} not walked"));
            let lc = &lazy.components.list[lazy.components.of_interval[i]];
            same_cycle(&walk(&lazy.space, lc), &walk(&full.space, c), 1e-9)
                .unwrap_or_else(|e| panic!("{name}: component {k}: {e}"));
        }
        assert_eq!(lazy.components.list.len(), full.components.list.len(), "{name}");
        // The drawn component keeps its index as components are added.
        assert_eq!(lazy.drawn_component, Some(kl));
        // A type with no realization there is reported as such, not walked.
        let bad = Realization { ty: lazy.drawn.ty.clone(), lambda: 1e6 };
        assert_eq!(lazy.include(&bad), None);
    }
}

#[test]
fn report_cli_says_which_analysis_it_did() {
    let dir = std::env::temp_dir().join(format!("caymos-lazy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("chain-40.toml");
    std::fs::write(&file, to_toml(&chain(40))).unwrap();
    let run = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_caymos")).args(args).output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        out.stdout
    };
    let json: serde_json::Value =
        serde_json::from_slice(&run(&["report", file.to_str().unwrap(), "--format", "json"])).unwrap();
    assert_eq!(json["analysis"], "lazy");
    assert_eq!(json["endpoint_method"], "lazy");
    assert_eq!(json["components"].as_array().unwrap().len(), 1);
    assert!(json["accuracy"]["max_relative_error_estimate"].as_f64().unwrap() < 1e-12);
    let text = String::from_utf8(run(&["report", file.to_str().unwrap()])).unwrap();
    assert!(text.contains("lazy: only the component through the drawn realization"), "{text}");
    let small: serde_json::Value =
        serde_json::from_slice(&run(&["report", "jansen", "--lazy", "--format", "json"])).unwrap();
    assert_eq!(small["analysis"], "lazy");
    let full: serde_json::Value = serde_json::from_slice(&run(&["report", "jansen", "--format", "json"])).unwrap();
    assert_eq!(full["analysis"], "full");
    std::fs::remove_dir_all(&dir).ok();
}

/// A four-bar whose interval is 1e-12 of its scale wide, [9.999999999999, 10]
/// on base A–C, drawn at the interval's upper end. Scaled by 1e150 the
/// drawing's λ (1e151) lies one ulp above the f64 sum of the stretched
/// step's lengths, where the walk once found no end and split the one
/// component in two.
#[test]
fn a_lazy_start_a_rounding_beyond_the_base_range_walks_the_one_component() {
    for scale in [1.0, 1e150, 1e-150] {
        let text = format!(
            "name = \"narrow\"\nground = [\"A\", \"D\"]\n\
             bars = [[\"A\", \"B\", {:e}], [\"B\", \"C\", {:e}], [\"C\", \"D\", {:e}], [\"D\", \"A\", {:e}]]\n\
             [joints]\nA = [0.0, 0.0]\nB = [{:e}, {:e}]\nC = [{:e}, 0.0]\nD = [{:e}, 0.0]\n",
            4.0 * scale,
            6.0 * scale,
            3.0 * scale,
            12.999999999999 * scale,
            3.9 * scale,
            0.5 * scale,
            10.0 * scale,
            13.0 * scale,
        );
        let scene = caymos::scene::parse_scene(&text, "narrow", "narrow").unwrap();
        // A–C and B–D, joints numbered as declared.
        for base in [[0, 2], [1, 3]] {
            let full = analyse_with(scene.clone(), Some(base), Scope::Full).unwrap().outcome.unwrap();
            let lazy = analyse_with(scene.clone(), Some(base), Scope::Lazy).unwrap().outcome.unwrap();
            // On B–D the sketch's drawn λ is out of its type's reach: a small scene then gets the full analysis.
            assert_eq!(lazy.lazy, base == [0, 2], "scale {scale:e}, base {base:?}");
            let count = |s: &Solved| (s.space.intervals.len(), s.components.list.len());
            assert_eq!(count(&full), (4, 1), "scale {scale:e}, base {base:?}");
            assert_eq!(count(&lazy), count(&full), "scale {scale:e}, base {base:?}");
            assert!(lazy.drawn_component.is_some(), "scale {scale:e}, base {base:?}");
            assert!(lazy.space.intervals.iter().all(|iv| !iv.upper.events.is_empty() && !iv.lower.events.is_empty()));
        }
    }
}

/// Every end of the 1000-step chain's drawn component has one flat step, as
/// a generic chain's ends must. At an end deep in the chain, the flat step's
/// f64 slack there read beyond the feasibility tolerance (1e-10 of the
/// scale) one way: placing it flat failed, every later step had no f64
/// value, and each was taken for flat too (one end listed 459 "coincident"
/// steps, another 4; the walk still closed). Two fixes, each enough here: a
/// step placed flat is placed whatever its slack, and a step without an f64
/// value is estimated from its double-double value alone, not taken for
/// flat. Only this long a chain showed it (none of 150–900 steps did).
#[test]
fn every_end_of_a_long_chain_has_one_flat_step() {
    let scene = chain(1000);
    let linkage = caymos::linkage::Linkage::from_scene(&scene);
    let dec = caymos::decompose::decompose(&linkage, scene.base.map(|b| b.0)).unwrap().unwrap();
    let con = caymos::realize::Construction::<f64>::new(&linkage, &dec).unwrap();
    let cert = caymos::certify::Certifier::new(&linkage, &dec).unwrap();
    let drawn = caymos::realize::drawn_realization(&linkage, &dec);
    let jet = con.convert::<Jet<f64>>();
    let space = component_through(&con, &cert, &jet, &drawn.ty, drawn.lambda, LazyOptions::default()).unwrap();
    assert_eq!(space.intervals.len(), 32);
    for iv in &space.intervals {
        for end in [&iv.lower, &iv.upper] {
            assert_eq!(end.events.len(), 1, "at λ = {}: {:?}", end.lambda, &end.events[..end.events.len().min(4)]);
        }
    }
    let c = components(&space);
    assert_eq!(c.list.len(), 1);
    assert!(c.list[0].closed);
}
