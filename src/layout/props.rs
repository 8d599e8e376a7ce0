//! Property tests of the geometry: compensation only adds, union is order-free, outputs are valid.
//! Shapes are compared by XOR area, never by vertex lists.

#[cfg(test)]
mod tests {
    use geo::Polygon;
    use proptest::prelude::*;

    use crate::drc::validity::problems;
    use crate::etch::compensation_design;
    use crate::layout::boolean::{area_um2, rect, union, xor_area_um2};
    use crate::layout::teeth::tooth_cell;
    use crate::process::CompensationGeometry;

    fn rects() -> impl Strategy<Value = Vec<Polygon>> {
        prop::collection::vec((0i32..60, 0i32..60, 1i32..25, 1i32..25), 1..25).prop_map(|v| {
            v.into_iter()
                .map(|(x, y, w, h)| {
                    rect(
                        f64::from(x),
                        f64::from(y),
                        f64::from(x + w),
                        f64::from(y + h),
                    )
                })
                .collect()
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(96))]

        #[test]
        fn compensated_tooth_contains_the_plain_one(
            top in 100.0f64..3000.0, depth in 10.0f64..300.0, ratio in 0.4f64..0.7,
            kind in 0usize..3, overlap in 1.0f64..20.0, width in 0.01f64..1.0,
        ) {
            let kind = [
                CompensationGeometry::CornerAttached,
                CompensationGeometry::Centred,
                CompensationGeometry::Bar110,
            ][kind];
            let bar = (kind == CompensationGeometry::Bar110).then_some(width * top);
            let c = compensation_design(depth, ratio, kind, bar);
            // layout::build rejects an overlap that swallows the whole square (LayoutError::CompensationOverlap).
            prop_assume!(kind != CompensationGeometry::CornerAttached || overlap < c.side_um);
            let comp = tooth_cell(top, Some(&c), overlap);
            let plain = tooth_cell(top, None, overlap);
            let mut both = comp.clone();
            both.extend(plain.iter().cloned());
            // plain is inside comp  <=>  comp u plain == comp
            prop_assert!(xor_area_um2(&union(&both), &comp) < 1e-3);
            prop_assert!(area_um2(&comp) > area_um2(&plain));
            for p in &comp {
                prop_assert!(problems(p, 4000).is_empty(), "{:?}", problems(p, 4000));
            }
        }

        #[test]
        fn union_area_does_not_depend_on_order(rs in rects(), seed in any::<u64>()) {
            let mut shuffled = rs.clone();
            // Deterministic shuffle from the seed.
            let mut s = seed | 1;
            for i in (1..shuffled.len()).rev() {
                s ^= s << 13; s ^= s >> 7; s ^= s << 17;
                shuffled.swap(i, (s % (i as u64 + 1)) as usize);
            }
            let (a, b) = (union(&rs), union(&shuffled));
            prop_assert!((area_um2(&a) - area_um2(&b)).abs() < 1e-6);
            prop_assert!(xor_area_um2(&a, &b) < 1e-6);
            let sum: f64 = a.iter().map(geo::Area::unsigned_area).sum();
            prop_assert!((sum - area_um2(&rs)).abs() < 1e-6, "pieces overlap: {} vs {}", sum, area_um2(&rs));
        }

        #[test]
        fn every_mask_set_polygon_is_valid(
            pattern in prop::sample::select(vec!["checkered", "matrix", "none"]),
            kind in prop::sample::select(vec!["corner_attached", "centred"]),
            pitch in 2600u32..3000, top in 1000u32..2000,
        ) {
            let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("process/mis-grasper.yaml");
            let sets = vec![
                format!("geometry.teeth.pattern={pattern}"),
                format!("steps.tmah-etch.compensation.geometry={kind}"),
                format!("geometry.teeth.pitch_x_um={pitch}"),
                format!("geometry.teeth.pitch_y_um={pitch}"),
                format!("geometry.teeth.top_um={top}"),
            ];
            let loaded = crate::process::load(&file, &sets).expect("valid overrides");
            let plan = crate::etch::plan(&loaded.process);
            let set = crate::layout::build(&loaded.process, &plan).expect("layout");
            let bad = crate::drc::validity::check(&set, 4000);
            prop_assert!(bad.is_empty(), "{:?}", bad);
        }

        #[test]
        fn every_union_polygon_is_valid(rs in rects()) {
            for p in union(&rs) {
                prop_assert!(problems(&p, 4000).is_empty(), "{:?}", problems(&p, 4000));
            }
        }
    }
}
