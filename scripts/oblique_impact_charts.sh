#!/bin/sh
# The two charts of doc/data/oblique_impact.csv (Chung & Ooi test 6; doc/contact_laws.md):
# doc/data/oblique_impact_et.png and oblique_impact_spin.png, with `trubal chart`. The data
# is written by `cargo test --profile ci --test it oblique_impact::write_the_comparison_chart
# -- --ignored`. TRUBAL_BIN selects the binary (default: cargo's release build).
set -e
cd "$(dirname "$0")/.."
if [ -z "$TRUBAL_BIN" ]; then
    cargo build --release --quiet
    TRUBAL_BIN=target/release/trubal
fi
csv=doc/data/oblique_impact.csv
chart() {
    "$TRUBAL_BIN" chart "$csv" --x angle --by law,fraction \
        --key exact/ --key mdr/0.2 --key md/0.2 --key md/0.01 --key walton/0.2 --key noslip/0.2 \
        --omit hm/0.2 --dashed exact/ \
        --label "exact/=exact (Hertz–Mindlin by the MDR)" --label "mdr/0.2=MDR, FRAction 0.2" \
        --label "md/0.2=MD (default), FRAction 0.2" --label "md/0.01=MD, FRAction 0.01" \
        --label "walton/0.2=WALTON, FRAction 0.2" --label "noslip/0.2=NOSLIP (= HM here), FRAction 0.2" \
        --xlabel "angle of incidence from the normal [°]" --xmin 0 --xmax 90 "$@"
}
chart --y et --ylabel "tangential restitution v_t'/v_t" \
    --title "Chung & Ooi (2011) test 6: alumina sphere on a rigid wall at 3.9 m/s" \
    --out doc/data/oblique_impact_et.png
chart --y spin --ylabel "rebound spin ω [rad/s]" \
    --title "Chung & Ooi (2011) test 6: rebound spin" --out doc/data/oblique_impact_spin.png
