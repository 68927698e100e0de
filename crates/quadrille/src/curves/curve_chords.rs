//! Chords of CAD curves (quasi-structured paper §4.3, spec §6.3): opposite
//! sides of a 4-sided CAD face should get the same number of mesh edges, or
//! the quad mesh needs an extra pair of irregular vertices to absorb the
//! difference. A chord is a class of curves linked through such faces
//! (union–find); every curve of a chord gets the same count, the rounded mean
//! of their ideal counts.

use geometry::vec3;
use geometry::{Face, Loop, Model};

use crate::core::union_find::UnionFind;
use crate::core::valence::ideal_corner_valence;

/// Two opposite curves join a chord only when their ideal counts differ by at
/// most this fraction of the larger one (the spec's τ: "very different" means
/// more than a 2:1 ratio).
pub const CHORD_TOLERANCE: f64 = 0.5;

/// An annulus's two loops are raised to one count when the larger ideal
/// count is at most this many times the smaller (a wider band than
/// [`CHORD_TOLERANCE`]'s 2 : 1): its ring grid then has no irregular vertex,
/// where unequal loops leave pairs of valence-3 and -5 vertices between them
/// (a hex nut's face around its bore: loops 3 : 1). The smaller loop only
/// gets finer.
pub const ANNULUS_RAISE_RATIO: f64 = 3.1;

/// Whether an annulus's loops of ideal counts `a` and `b` get one count
/// (the larger, see [`ANNULUS_RAISE_RATIO`]).
pub fn annulus_counts_agree(a: f64, b: f64) -> bool {
    a > 0.0 && b > 0.0 && a.max(b) <= ANNULUS_RAISE_RATIO * a.min(b)
}

/// The curves of each 4-sided face taken as opposite pairs: faces with one
/// loop of exactly four uses, none of them a degenerate curve, and faces
/// with such a loop around a hole bounded by one closed curve (the
/// [`crate::direct::holed_face`] grid needs equal opposite sides too); and
/// the two loops of an annulus of one curve each ([`annulus_loops`]: the
/// ring grid of `direct::ring_face` needs equal counts on both).
pub fn opposite_pairs(model: &Model) -> Vec<[usize; 2]> {
    let mut pairs = Vec::new();
    for f in &model.faces {
        if let Some(loops) = annulus_loops(model, f) {
            if let [[a], [b]] = [loops[0].as_slice(), loops[1].as_slice()] {
                pairs.push([*a, *b]);
            }
            continue;
        }
        let outer = match f.loops.as_slice() {
            [lp] => lp,
            [a, b] if a.uses.len() == 4 && b.uses.len() == 1 => a,
            [a, b] if b.uses.len() == 4 && a.uses.len() == 1 => b,
            _ => continue,
        };
        if outer.uses.len() != 4 {
            continue;
        }
        let c: Vec<usize> = outer.uses.iter().map(|u| u.curve.idx()).collect();
        if c.iter().any(|&i| model.curves[i].degenerate) {
            continue;
        }
        pairs.push([c[0], c[2]]);
        pairs.push([c[1], c[3]]);
    }
    pairs
}

/// Chord class of every curve (the smallest curve index of its class), given
/// each curve's ideal count `ideal[c]`: opposite curves whose ideal counts
/// differ by at most [`CHORD_TOLERANCE`] × the larger are united.
pub fn chord_classes(model: &Model, ideal: &[f64]) -> Vec<usize> {
    let mut uf = UnionFind::new(model.curves.len());
    for [a, b] in opposite_pairs(model) {
        if (ideal[a] - ideal[b]).abs() <= CHORD_TOLERANCE * ideal[a].max(ideal[b]) {
            uf.union(a, b);
        }
    }
    (0..model.curves.len()).map(|i| uf.find(i)).collect()
}

/// Counts from ideal counts: each chord gets `round(mean ideal)`, at least 1.
pub fn chord_counts(classes: &[usize], ideal: &[f64]) -> Vec<usize> {
    let n = classes.len();
    let (mut sum, mut num) = (vec![0.0; n], vec![0usize; n]);
    for i in 0..n {
        sum[classes[i]] += ideal[i];
        num[classes[i]] += 1;
    }
    (0..n)
        .map(|i| {
            (sum[classes[i]] / num[classes[i]] as f64)
                .round()
                .clamp(1.0, 1.0e6) as usize
        })
        .collect()
}

/// Interior angle (radians, measured on the surface) of loop `lp` of `face`
/// where use `k` starts, between the previous use's end tangent and this
/// use's start tangent; `None` when either use is a degenerate curve (a pole
/// has no tangent) or the angle is undefined.
pub fn use_start_angle(model: &Model, face: &Face, lp: &Loop, k: usize) -> Option<f64> {
    let n = lp.uses.len();
    let u = &lp.uses[k];
    let prev = &lp.uses[(k + n - 1) % n];
    let (ce, pce) = (
        &model.curves[u.curve.idx()],
        &model.curves[prev.curve.idx()],
    );
    if ce.degenerate || pce.degenerate {
        return None;
    }
    let t_prev = if prev.forward {
        pce.range.1
    } else {
        pce.range.0
    };
    let t_here = if u.forward { ce.range.0 } else { ce.range.1 };
    let uv = u.pcurve.eval(t_here);
    let sgn = |fwd: bool| if fwd { 1.0 } else { -1.0 };
    let d_in = prev.pcurve.deriv(t_prev).map(|x| x * sgn(prev.forward));
    let d_out = u.pcurve.deriv(t_here).map(|x| x * sgn(u.forward));
    let d = face.surface.derivs(uv);
    let lift = |t: [f64; 2]| vec3::add(vec3::scale(d.du, t[0]), vec3::scale(d.dv, t[1]));
    let (a, b) = (lift(d_in), lift(d_out));
    let normal = vec3::cross(d.du, d.dv);
    let turn = vec3::dot(normal, vec3::cross(a, b)).atan2(vec3::dot(a, b) * vec3::norm(normal));
    let angle = std::f64::consts::PI - turn;
    angle.is_finite().then_some(angle)
}

/// Interior angle, in 3D, at the pole of degenerate use `k` of loop `lp`:
/// between the curves that reach it and leave it (`None` when a neighbour is
/// degenerate too or a tangent vanishes). The same angle as the pattern
/// mesher measures between the pole's ring neighbours.
fn pole_angle(model: &Model, lp: &Loop, k: usize) -> Option<f64> {
    let n = lp.uses.len();
    let (prev, next) = (&lp.uses[(k + n - 1) % n], &lp.uses[(k + 1) % n]);
    let tangent = |u: &geometry::CurveUse, at_start: bool| -> Option<vec3::Vec3> {
        let ce = &model.curves[u.curve.idx()];
        let g = ce.geom.as_ref()?;
        // the loop runs from range.0 to range.1 when forward
        let t = if at_start == u.forward {
            ce.range.0
        } else {
            ce.range.1
        };
        let d = g.deriv(t);
        // pointing away from the pole
        let away = if at_start == u.forward { 1.0 } else { -1.0 };
        vec3::normalize(vec3::scale(d, away))
    };
    let a = tangent(prev, false)?;
    let b = tangent(next, true)?;
    let angle = vec3::dot(a, b).clamp(-1.0, 1.0).acos();
    angle.is_finite().then_some(angle)
}

/// The sides of a face for a pattern (paper §6.1.2): a face bounded by one
/// loop whose corners are convex (ideal valence 1, [`ideal_corner_valence`])
/// or flat (2, inside a side), at least 3 convex; for each side, its curves
/// in loop order (a pole is a corner, or a flat point, with no curve; a pole
/// corner where one quad would fold rules the face out, as in
/// [`crate::direct::pattern_face`]).
/// `None` for any other face (holes, a concave corner). A cylinder band
/// whose one end is split into arcs has four sides: the full circle, the
/// seam, the arcs, the seam.
pub fn convex_sides(model: &Model, face: &Face) -> Option<Vec<Vec<usize>>> {
    let [lp] = face.loops.as_slice() else {
        return None;
    };
    let n = lp.uses.len();
    let degenerate = |k: usize| model.curves[lp.uses[k % n].curve.idx()].degenerate;
    if (0..n).all(degenerate) {
        return None;
    }
    // a corner at use k's start (or at its pole, for a degenerate use)
    let mut corners = Vec::new();
    for k in 0..n {
        let angle = if degenerate(k) {
            pole_angle(model, lp, k)?
        } else if degenerate(k + n - 1) {
            continue;
        } else {
            use_start_angle(model, face, lp, k)?
        };
        match ideal_corner_valence(angle) {
            // as the pattern mesher: no pattern puts one quad on a pole
            1 if degenerate(k)
                && crate::core::queries::folds_at_pole(
                    face,
                    face.pole_segment(&lp.uses[k], &model.curves[lp.uses[k].curve.idx()]),
                ) =>
            {
                return None
            }
            1 => corners.push(k),
            2 => {}
            _ => return None,
        }
    }
    if corners.len() < 3 {
        return None;
    }
    let m = corners.len();
    Some(
        (0..m)
            .map(|i| {
                let (a, b) = (corners[i], corners[(i + 1) % m]);
                let len = (b + n - a) % n;
                (0..len)
                    .map(|j| (a + j) % n)
                    .filter(|&k| !degenerate(k))
                    .map(|k| lp.uses[k].curve.idx())
                    .collect()
            })
            .collect(),
    )
}

/// Smallest interior angle of a loop corner that a ring grid takes
/// ([`ring_junction`]): the grid line from the corner splits it into two
/// quad corners of at least 57.5° each (a hexagon's 120° corners: two of
/// 60°, the SICN of the one 120° corner its ideal valence asks for).
pub const RING_CORNER_MIN_ANGLE: f64 = 115.0 * std::f64::consts::PI / 180.0;

/// Whether a loop junction of interior angle `angle` (radians) can be a node
/// of a ring grid, where every loop node has two quads: a flat junction
/// (ideal valence 2) or an obtuse corner of at least [`RING_CORNER_MIN_ANGLE`].
pub fn ring_junction(angle: f64) -> bool {
    ideal_corner_valence(angle) == 2
        || (angle >= RING_CORNER_MIN_ANGLE && angle < std::f64::consts::PI)
}

/// The curves of each loop of an annulus meshed as a ring grid
/// (`direct::ring_face`): a face with two loops, every junction of either
/// flat (smooth loops: a circle, or a circle split into arcs) or an obtuse
/// corner ([`ring_junction`]: a hex nut's face), no degenerate curve, on a
/// surface that is not periodic (a periodic band has a seam and is a
/// 4-sided grid instead). `None` for any other face.
pub fn annulus_loops(model: &Model, face: &Face) -> Option<[Vec<usize>; 2]> {
    let [l0, l1] = face.loops.as_slice() else {
        return None;
    };
    if face.surface.periods().iter().any(Option::is_some) {
        return None;
    }
    let curves = |lp: &Loop| -> Option<Vec<usize>> {
        for (k, u) in lp.uses.iter().enumerate() {
            if model.curves[u.curve.idx()].degenerate
                || !ring_junction(use_start_angle(model, face, lp, k)?)
            {
                return None;
            }
        }
        Some(lp.uses.iter().map(|u| u.curve.idx()).collect())
    };
    Some([curves(l0)?, curves(l1)?])
}

/// The four sides of a face with exactly four convex corners and only flat
/// other junctions ([`convex_sides`]).
pub fn four_sides(model: &Model, face: &Face) -> Option<[Vec<usize>; 4]> {
    convex_sides(model, face)?.try_into().ok()
}

/// Sides made of several curves facing a side of one curve (see
/// [`four_sides`]): the single curve's chord gets the sum of the other
/// side's counts, so the face can be a grid, when the ideal counts agree
/// within [`CHORD_TOLERANCE`] and the two sides share no curve. `members(c)`
/// lists the curves of `c`'s chord (all set together, as chords are equal).
/// Passes over the faces repeat while they change something (a face's
/// balance can move a curve of another face's side), at most
/// [`BALANCE_PASSES`] times: conflicting constraints are left as the last
/// pass sets them. An annulus (hole and outer loop as opposite sides) with a
/// cornered loop is balanced only when [`raise_contained`]; such a contained
/// annulus may also raise its single curve up to [`ANNULUS_RAISE_RATIO`].
/// Returns, per curve, whether such a raise beyond [`CHORD_TOLERANCE`] set
/// its count (its bands' seams are left at their own count, see
/// `count_balance::square_band_seams`).
pub fn balance_composite_sides(
    model: &Model,
    ideal: &[f64],
    counts: &mut [usize],
    members: &impl Fn(usize) -> Vec<usize>,
) -> Vec<bool> {
    // an annulus whose loops are one curve and several arcs is balanced
    // like two opposite sides (its other two "sides" empty)
    let sides_of: Vec<Option<([Vec<usize>; 4], bool)>> = model
        .faces
        .iter()
        .map(|f| {
            four_sides(model, f).map(|s| (s, false)).or_else(|| {
                annulus_loops(model, f).map(|[a, b]| ([a, Vec::new(), b, Vec::new()], true))
            })
        })
        .collect();
    let curve_faces = model.curve_faces();
    let sided: Vec<([Vec<usize>; 4], Option<AnnulusRaise>)> = sides_of
        .iter()
        .enumerate()
        .filter_map(|(f, s)| s.as_ref().map(|s| (f, s)))
        .map(|(f, (s, annulus))| {
            let raise = annulus.then(|| AnnulusRaise {
                cornered: loops_have_corner(model, &model.faces[f]),
                contained: raise_contained(model, s, &sides_of, &curve_faces, ideal, members),
            });
            (s.clone(), raise)
        })
        .collect();
    let mut raised_to = vec![None; counts.len()];
    for _ in 0..BALANCE_PASSES {
        if !balance_pass(&sided, ideal, counts, members, &mut raised_to) {
            break;
        }
    }
    // a later pass may have set the chord again (a face of the chain
    // balanced to another count): only the counts a raise still holds
    (0..counts.len())
        .map(|c| raised_to[c] == Some(counts[c]))
        .collect()
}

/// What [`balance_pass`] may do to an annulus's single-curve loop.
#[derive(Clone, Copy, Debug)]
struct AnnulusRaise {
    /// A loop has a corner (a hex nut's face, see [`ring_junction`]): its
    /// loop's count moves only when the raise is `contained`.
    cornered: bool,
    /// [`raise_contained`]: the loop may also be raised beyond
    /// [`CHORD_TOLERANCE`], up to [`ANNULUS_RAISE_RATIO`].
    contained: bool,
}

/// Whether a loop of `face` has a junction that is not flat (ideal valence
/// other than 2, as a hexagon's corners).
fn loops_have_corner(model: &Model, face: &Face) -> bool {
    face.loops.iter().any(|lp| {
        (0..lp.uses.len()).any(|k| {
            use_start_angle(model, face, lp, k).is_some_and(|a| ideal_corner_valence(a) != 2)
        })
    })
}

/// Whether raising the single-curve loop of an annulus with loops `sides`
/// (`[outer or hole, -, the other, -]`, see [`balance_composite_sides`]) to
/// its other loop's count stays in the annulus's own band chain: every face
/// that a curve of the single curve's chord bounds (`curve_faces`, faces'
/// sides in `sides_of`) is a band passing the chord on (a 4-sided face whose
/// side of that curve and the opposite side are single curves of the
/// chord: a bore's cylinder, a chamfer's cone) or an annulus whose loop of
/// that curve is single and whose other loop has several curves of about
/// the same ideal total (within [`CHORD_TOLERANCE`]: the opposite end face
/// of a hex nut). A chord reaching any other face (a screw's shank running
/// on into its end face or thread) would carry the finer count there.
fn raise_contained(
    model: &Model,
    sides: &[Vec<usize>; 4],
    sides_of: &[Option<([Vec<usize>; 4], bool)>],
    curve_faces: &[Vec<geometry::FaceId>],
    ideal: &[f64],
    members: &impl Fn(usize) -> Vec<usize>,
) -> bool {
    let total = |s: &[usize]| s.iter().map(|&c| ideal[c]).sum::<f64>();
    let (single, many) = match (sides[0].as_slice(), sides[2].as_slice()) {
        ([c], m) if m.len() >= 2 => (*c, m),
        (m, [c]) if m.len() >= 2 => (*c, m),
        _ => return false,
    };
    let want = total(many);
    let chord = members(single);
    chord.iter().all(|&m| {
        curve_faces[m].iter().all(|f| {
            let Some((s, annulus)) = &sides_of[f.idx()] else {
                // a band with a seam: one loop of four uses, the chord's
                // curve facing another of the chord
                let [lp] = model.faces[f.idx()].loops.as_slice() else {
                    return false;
                };
                let n = lp.uses.len();
                return n == 4
                    && (0..n).all(|k| {
                        lp.uses[k].curve.idx() != m
                            || chord.contains(&lp.uses[(k + 2) % n].curve.idx())
                    });
            };
            let Some(k) = s.iter().position(|side| side.as_slice() == [m]) else {
                return false;
            };
            let opposite = &s[(k + 2) % 4];
            if *annulus {
                opposite.len() >= 2
                    && (total(opposite) - want).abs() <= CHORD_TOLERANCE * total(opposite).max(want)
            } else {
                matches!(opposite.as_slice(), [o] if chord.contains(o))
            }
        })
    })
}

/// Passes of [`balance_composite_sides`], at most.
pub const BALANCE_PASSES: usize = 8;

/// One pass of [`balance_composite_sides`] over the four-sided faces'
/// `sided` (an annulus flagged with its [`AnnulusRaise`]), noting in
/// `raised_to` the count a raise beyond [`CHORD_TOLERANCE`] set on each of
/// its curves; true when a count changed.
fn balance_pass(
    sided: &[([Vec<usize>; 4], Option<AnnulusRaise>)],
    ideal: &[f64],
    counts: &mut [usize],
    members: &impl Fn(usize) -> Vec<usize>,
    raised_to: &mut [Option<usize>],
) -> bool {
    let mut changed = false;
    for (sides, raise) in sided {
        for (a, b) in [(0, 2), (2, 0), (1, 3), (3, 1)] {
            let ([single], many) = (sides[a].as_slice(), &sides[b]) else {
                continue;
            };
            // a curve of the many in the single's chord: equal totals
            // would need n = n + the others' counts, and each pass would
            // raise the chord again
            let chord = members(*single);
            if many.len() < 2 || many.iter().any(|c| chord.contains(c)) {
                continue;
            }
            let sum: usize = many.iter().map(|&c| counts[c]).sum();
            let ideal_sum: f64 = many.iter().map(|&c| ideal[c]).sum();
            let within = (ideal[*single] - ideal_sum).abs()
                <= CHORD_TOLERANCE * ideal[*single].max(ideal_sum);
            // a contained annulus's single curve may be raised farther,
            // never lowered; a cornered annulus's moves only when contained
            let (agree, beyond) = match raise {
                None => (within, false),
                Some(r) => {
                    let farther = r.contained
                        && sum > counts[*single]
                        && annulus_counts_agree(ideal[*single], ideal_sum);
                    (
                        (within && (!r.cornered || r.contained)) || farther,
                        farther && !within,
                    )
                }
            };
            if counts[*single] != sum && agree {
                for c in chord {
                    counts[c] = sum;
                    if beyond {
                        raised_to[c] = Some(sum);
                    }
                }
                changed = true;
            }
        }
    }
    changed
}

/// Ring edges of each side under the coarse `counts`: a curve of `n`
/// coarse segments puts `2n` edges on the face's boundary ring (spec §1.2).
fn ring_side_counts(sides: &[Vec<usize>], counts: &[usize]) -> Vec<u32> {
    sides
        .iter()
        .map(|s| s.iter().map(|&c| 2 * counts[c] as u32).sum())
        .collect()
}

/// Answers the pattern searches of the side counts `rings` not in `known`
/// yet, in parallel, and stores them (the same answers [`has_pattern`] would
/// find one by one).
fn learn_patterns(
    rings: impl Iterator<Item = Vec<u32>>,
    known: &mut std::collections::HashMap<Vec<u32>, bool>,
) {
    use rayon::prelude::*;
    let mut fresh: Vec<Vec<u32>> = rings.filter(|r| !known.contains_key(r)).collect();
    fresh.sort_unstable();
    fresh.dedup();
    let found: Vec<bool> = fresh
        .par_iter()
        .with_max_len(1)
        .map(|r| crate::combinatorics::patterns::match_pattern(r).is_some())
        .collect();
    known.extend(fresh.into_iter().zip(found));
}

/// True when a library pattern meshes a face with `sides` under `counts`;
/// `known` remembers the answers by side counts.
fn has_pattern(
    sides: &[Vec<usize>],
    counts: &[usize],
    known: &mut std::collections::HashMap<Vec<u32>, bool>,
) -> bool {
    let ring = ring_side_counts(sides, counts);
    if let Some(&fits) = known.get(&ring) {
        return fits;
    }
    let fits = crate::combinatorics::patterns::match_pattern(&ring).is_some();
    known.insert(ring, fits);
    fits
}

/// Most sides of a face [`balance_for_patterns`] considers (the library's
/// patterns have 3, 4 or 5).
const PATTERN_MAX_SIDES: usize = 5;

/// Nudges curve counts so that more faces can be meshed by a pattern (paper
/// §6.1.2): for each face with [`convex_sides`] that no library pattern
/// fits, every curve of its boundary is tried one coarse segment up and one
/// down (with its whole chord, `members`, never below `min_count`), and the
/// change that makes the most faces fit a pattern, counted over the faces of
/// the changed curves, is kept when it adds at least one; ties go to the
/// counts closest to their `ideal`. Two passes over the faces.
pub fn balance_for_patterns(
    model: &Model,
    ideal: &[f64],
    counts: &mut [usize],
    members: &impl Fn(usize) -> Vec<usize>,
    min_count: &impl Fn(usize) -> usize,
) {
    use rayon::prelude::*;
    // the faces' sides (corner angles on the CAD), side by side
    let faces: Vec<Vec<Vec<usize>>> = model
        .faces
        .par_iter()
        .filter_map(|f| convex_sides(model, f))
        .filter(|s| s.len() <= PATTERN_MAX_SIDES && s.iter().all(|x| !x.is_empty()))
        .collect();
    let mut faces_of: Vec<Vec<usize>> = vec![Vec::new(); model.curves.len()];
    for (fi, sides) in faces.iter().enumerate() {
        for &c in sides.iter().flatten() {
            if !faces_of[c].contains(&fi) {
                faces_of[c].push(fi);
            }
        }
    }
    // the pattern search answers by side counts alone: each asked once
    // (on i15o_s8 the planning took 30 ms, mostly the same searches again)
    let mut known = std::collections::HashMap::new();
    learn_patterns(
        faces.iter().map(|s| ring_side_counts(s, counts)),
        &mut known,
    );
    let mut fits: Vec<bool> = faces
        .iter()
        .map(|s| has_pattern(s, counts, &mut known))
        .collect();
    for _ in 0..2 {
        for fi in 0..faces.len() {
            if fits[fi] {
                continue;
            }
            let mut curves: Vec<usize> = faces[fi].iter().flatten().copied().collect();
            curves.sort_unstable();
            curves.dedup();
            // the searches the candidates below will ask, answered first in parallel
            let mut asked: Vec<Vec<u32>> = Vec::new();
            let mut trial = counts.to_vec();
            for &c in &curves {
                let chord = members(c);
                for up in [true, false] {
                    if !up && chord.iter().any(|&m| counts[m] <= min_count(m)) {
                        continue;
                    }
                    for &m in &chord {
                        trial[m] = if up { counts[m] + 1 } else { counts[m] - 1 };
                    }
                    asked.push(ring_side_counts(&faces[fi], &trial));
                    for &m in &chord {
                        asked.extend(
                            faces_of[m]
                                .iter()
                                .map(|&f| ring_side_counts(&faces[f], &trial)),
                        );
                    }
                    for &m in &chord {
                        trial[m] = counts[m];
                    }
                }
            }
            learn_patterns(asked.into_iter(), &mut known);
            // (faces gained, deviation from the ideal, curve, step)
            let mut best: Option<(i64, f64, usize, bool)> = None;
            for &c in &curves {
                let chord = members(c);
                for up in [true, false] {
                    if !up && chord.iter().any(|&m| counts[m] <= min_count(m)) {
                        continue;
                    }
                    let step = |counts: &mut [usize], forward: bool| {
                        for &m in &chord {
                            counts[m] = if forward == up {
                                counts[m] + 1
                            } else {
                                counts[m] - 1
                            };
                        }
                    };
                    step(counts, true);
                    let mut touched: Vec<usize> = chord
                        .iter()
                        .flat_map(|&m| faces_of[m].iter().copied())
                        .collect();
                    touched.sort_unstable();
                    touched.dedup();
                    let gained: i64 = touched
                        .iter()
                        .map(|&f| {
                            has_pattern(&faces[f], counts, &mut known) as i64 - fits[f] as i64
                        })
                        .sum();
                    let deviation: f64 = chord
                        .iter()
                        .map(|&m| (counts[m] as f64 - ideal[m]).abs() / ideal[m].max(0.5))
                        .sum();
                    if gained > 0
                        && has_pattern(&faces[fi], counts, &mut known)
                        && best.is_none_or(|b| gained > b.0 || (gained == b.0 && deviation < b.1))
                    {
                        best = Some((gained, deviation, c, up));
                    }
                    step(counts, false);
                }
            }
            if let Some((_, _, c, up)) = best {
                let chord = members(c);
                for &m in &chord {
                    counts[m] = if up { counts[m] + 1 } else { counts[m] - 1 };
                }
                for &m in &chord {
                    for &f in &faces_of[m] {
                        fits[f] = has_pattern(&faces[f], counts, &mut known);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn ring_junctions_are_flat_or_obtuse_corners() {
        let deg = |d: f64| d.to_radians();
        // a hexagon's 120° corner: two quads of 60°; a square's 90° and a
        // 110° corner: one quad each; flat and slightly reflex: two quads
        assert!(super::ring_junction(deg(120.0)));
        assert!(super::ring_junction(deg(115.0)));
        assert!(!super::ring_junction(deg(110.0)));
        assert!(!super::ring_junction(deg(90.0)));
        assert!(super::ring_junction(deg(180.0)));
        assert!(super::ring_junction(deg(220.0)));
        // a reflex corner wants three quads
        assert!(!super::ring_junction(deg(250.0)));
    }

    #[test]
    fn annulus_loops_agree_up_to_the_raise_ratio() {
        assert!(super::annulus_counts_agree(36.0, 108.0));
        assert!(super::annulus_counts_agree(108.0, 36.0));
        assert!(!super::annulus_counts_agree(10.0, 32.0));
        assert!(!super::annulus_counts_agree(0.0, 4.0));
    }

    use super::*;
    use geometry::primitives;

    /// Sides of a nut-like chain: annulus 0 (hexagon curves 0–2 around the
    /// bore curve 3), band 1 (curve 3 facing curve 5, seam 4), annulus 2
    /// (hexagon 6–8 around curve 5), and band 3 (curve 5 facing curve 9,
    /// seam 10) when `shank`: the bore's chord {3, 5} runs on into it.
    #[allow(clippy::type_complexity)]
    fn nut_chain(
        shank: bool,
    ) -> (
        Vec<Option<([Vec<usize>; 4], bool)>>,
        Vec<Vec<geometry::FaceId>>,
    ) {
        use geometry::FaceId;
        let mut sides = vec![
            Some(([vec![0, 1, 2], vec![], vec![3], vec![]], true)),
            Some(([vec![3], vec![4], vec![5], vec![4]], false)),
            Some(([vec![6, 7, 8], vec![], vec![5], vec![]], true)),
        ];
        let mut faces: Vec<Vec<FaceId>> = vec![Vec::new(); 11];
        for (c, f) in [
            (0, 0),
            (1, 0),
            (2, 0),
            (3, 0),
            (3, 1),
            (4, 1),
            (5, 1),
            (5, 2),
            (6, 2),
            (7, 2),
            (8, 2),
        ] {
            faces[c].push(FaceId(f));
        }
        if shank {
            sides.push(Some(([vec![5], vec![10], vec![9], vec![10]], false)));
            faces[5].push(FaceId(3));
        }
        (sides, faces)
    }

    #[test]
    fn an_annulus_raise_is_contained_only_inside_its_band_chain() {
        // hexagons of ideal total 36 around bores of 12 (3 : 1)
        let mut ideal = vec![12.0; 11];
        let members = |c: usize| {
            if c == 3 || c == 5 {
                vec![3, 5]
            } else {
                vec![c]
            }
        };
        let model = primitives::square(1.0);
        let (sides, faces) = nut_chain(false);
        let s0 = sides[0].clone().unwrap().0;
        assert!(raise_contained(
            &model, &s0, &sides, &faces, &ideal, &members
        ));
        // the chord reaches a band whose far side (9) is not in the chord
        let (sides_s, faces_s) = nut_chain(true);
        assert!(!raise_contained(
            &model, &s0, &sides_s, &faces_s, &ideal, &members
        ));
        // the far end face's hexagon (total 9) would not want the raise
        for c in 6..9 {
            ideal[c] = 3.0;
        }
        assert!(!raise_contained(
            &model, &s0, &sides, &faces, &ideal, &members
        ));
    }

    #[test]
    fn a_contained_cornered_annulus_raises_its_bore_and_an_uncontained_one_keeps_it() {
        let ideal = vec![12.0; 11];
        let members = |c: usize| {
            if c == 3 || c == 5 {
                vec![3, 5]
            } else {
                vec![c]
            }
        };
        let (sides, _) = nut_chain(false);
        let sided =
            |cornered: bool, contained: bool| -> Vec<([Vec<usize>; 4], Option<AnnulusRaise>)> {
                sides
                    .iter()
                    .flatten()
                    .map(|(s, a)| {
                        (
                            s.clone(),
                            a.then_some(AnnulusRaise {
                                cornered,
                                contained,
                            }),
                        )
                    })
                    .collect()
            };
        let mut counts = vec![12usize; 11];
        let mut raised = vec![None; 11];
        assert!(balance_pass(
            &sided(true, true),
            &ideal,
            &mut counts,
            &members,
            &mut raised
        ));
        assert_eq!((counts[3], counts[5]), (36, 36));
        assert_eq!(raised.iter().filter(|r| r.is_some()).count(), 2);
        assert_eq!((raised[3], raised[5]), (Some(36), Some(36)));
        // hexagons of ideal total 18 around bores of 12 agree within the
        // tolerance: a smooth annulus balances (bore 18, as on main), a
        // cornered one whose raise is not contained keeps its bore at 12
        let mut ideal = ideal;
        for c in [0, 1, 2, 6, 7, 8] {
            ideal[c] = 6.0;
        }
        for (cornered, want) in [(false, 18usize), (true, 12)] {
            let mut counts = vec![6usize; 11];
            counts[3] = 12;
            counts[5] = 12;
            let mut raised = vec![None; 11];
            balance_pass(
                &sided(cornered, false),
                &ideal,
                &mut counts,
                &members,
                &mut raised,
            );
            assert_eq!((counts[3], counts[5]), (want, want), "cornered {cornered}");
            assert!(raised.iter().all(Option::is_none));
        }
    }

    /// The paper's example: ideal counts [9.4, 4.1, 10.6, 3.9] on a
    /// rectangle give [10, 4, 10, 4], where plain rounding gives [9, 4, 11, 4].
    #[test]
    fn the_papers_rectangle_gets_equal_opposite_counts() {
        let m = primitives::square(1.0);
        let ideal = [9.4, 4.1, 10.6, 3.9];
        let classes = chord_classes(&m, &ideal);
        assert_eq!(chord_counts(&classes, &ideal), vec![10, 4, 10, 4]);
    }

    #[test]
    fn very_different_opposite_sides_stay_apart() {
        let m = primitives::square(1.0);
        let ideal = [9.0, 4.0, 20.0, 4.0];
        let classes = chord_classes(&m, &ideal);
        assert_eq!(chord_counts(&classes, &ideal), vec![9, 4, 20, 4]);
    }

    /// The lateral face of a cylinder is 4-sided: circle, seam, circle, seam.
    #[test]
    fn cylinder_circles_form_one_chord() {
        let m = primitives::cylinder(1.0, 2.0);
        let classes = chord_classes(&m, &[12.3, 12.4, 2.0]);
        assert_eq!(classes[0], classes[1]);
        assert_ne!(classes[0], classes[2]);
    }

    #[test]
    fn a_side_of_two_curves_gets_the_count_of_the_side_it_faces() {
        // a 4 × 1 rectangle whose bottom is split at (2, 0): five curves, four
        // convex corners, the flat junction inside the bottom side
        let m = primitives::polygon(&[[0.0, 0.0], [2.0, 0.0], [4.0, 0.0], [4.0, 1.0], [0.0, 1.0]]);
        let sides = four_sides(&m, &m.faces[0]).expect("four sides");
        let mut sorted = sides.to_vec();
        sorted.sort();
        assert_eq!(sorted, vec![vec![0, 1], vec![2], vec![3], vec![4]]);
        // at coarse spacing 0.6 the top's ideal count is 6.67 (7) and the
        // halves' 3.33 (3 each): the top takes their sum
        let ideal = [10.0 / 3.0, 10.0 / 3.0, 5.0 / 3.0, 20.0 / 3.0, 5.0 / 3.0];
        let classes = chord_classes(&m, &ideal);
        let mut counts = chord_counts(&classes, &ideal);
        assert_eq!(counts, vec![3, 3, 2, 7, 2]);
        balance_composite_sides(&m, &ideal, &mut counts, &|c| vec![c]);
        assert_eq!(counts, vec![3, 3, 2, 6, 2]);
        // the whole planner does the same
        let plan = crate::curves::curve_mesh::plan_curves(&m, 0.3);
        assert_eq!(plan.counts[3], plan.counts[0] + plan.counts[1]);
        // a plain rectangle has no composite side: nothing changes
        let r = primitives::rectangle(4.0, 1.0);
        let ideal = [6.6, 1.7, 6.8, 1.6];
        let mut counts = chord_counts(&chord_classes(&r, &ideal), &ideal);
        let before = counts.clone();
        balance_composite_sides(&r, &ideal, &mut counts, &|c| vec![c]);
        assert_eq!(counts, before);
    }

    #[test]
    fn sides_too_different_keep_their_counts() {
        // the top is three times the bottom halves' total in ideal count
        let m = primitives::polygon(&[[0.0, 0.0], [2.0, 0.0], [4.0, 0.0], [4.0, 1.0], [0.0, 1.0]]);
        let ideal = [1.0, 1.0, 2.0, 6.0, 2.0];
        let mut counts = chord_counts(&chord_classes(&m, &ideal), &ideal);
        balance_composite_sides(&m, &ideal, &mut counts, &|c| vec![c]);
        assert_eq!(counts, vec![1, 1, 2, 6, 2]);
    }

    #[test]
    fn a_triangle_gets_counts_its_pattern_accepts() {
        // a triangle's pattern (three quads around a valence-3 vertex) needs
        // each side shorter than the other two together: coarse counts
        // [2, 2, 4] have none; the long side one down (closest to its ideal)
        // gives [2, 2, 3]
        let m = primitives::polygon(&[[0.0, 0.0], [2.0, 0.0], [1.0, 1.7]]);
        let sides = convex_sides(&m, &m.faces[0]).expect("three convex corners");
        assert_eq!(sides, vec![vec![0], vec![1], vec![2]]);
        let ideal = [2.2, 2.1, 3.9];
        let mut counts = vec![2, 2, 4];
        assert!(!has_pattern(&sides, &counts, &mut Default::default()));
        balance_for_patterns(&m, &ideal, &mut counts, &|c| vec![c], &|_| 1);
        assert_eq!(counts, vec![2, 2, 3]);
        assert!(has_pattern(&sides, &counts, &mut Default::default()));
        // counts a pattern already accepts stay
        let mut fine = vec![2, 2, 2];
        balance_for_patterns(&m, &ideal, &mut fine, &|c| vec![c], &|_| 1);
        assert_eq!(fine, vec![2, 2, 2]);
    }
}
