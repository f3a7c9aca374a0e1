#!/usr/bin/env bash
# Golden hashes: the SHA-256 of `vrpd sample`'s CSV for a table of cases (one and two radii,
# sizing fields under each rule, hierarchies, both boundaries, several boxes), on every device.
# A change that moves a point fails here, so moving one is always deliberate: rerun with --print
# to get the new table, and say why in the commit.
# Usage: golden.sh VRPD [--print] [DEVICE...]   (devices default to cpu gpu serial)
set -uo pipefail
set -f  # the sizing expressions hold * and ( ): never globs
vrpd=$1
shift
print=0
if [ "${1:-}" = "--print" ]; then print=1; shift; fi
devices=("$@")
[ ${#devices[@]} -gt 0 ] || devices=(cpu gpu serial)

# sha256 of the CSV | sample arguments
table=$(cat <<'EOF'
3591aace2b4fbebbb40500762b5b6fb922c6d5656143f93aef676dd29519330e | --radius 0.01 --seed 1
82d88b3ea3c2c0e4e20b450518bc9d7d400337b8cea6adbca822f533e4b1bc4a | --radius 0.004 --seed 2
8d6cab0a5d109a12fc3c4bf7e910f6535367d52cb77f1b5f53d331723403471d | --radius 0.02 --boundary free --seed 3
3f129e1c17dd228d8de4a4b952df2b77fcd6af3d237dfbe7a63df830ed0bc941 | --radius 0.01 --extent 2,1 --seed 4
c67603142470aabb4d90262c1d4b37e1e8e0004eaf8f6599d43b27b8dafce20d | --radius 3 --extent 192,108 --boundary free --seed 5
811463f2e480cafa11fee8e1a923f487305bd2461a5f3873d424982874557ebd | --radius 0.05 --extent 1,3 --boundary free --seed 6
8fc7d78fd920ab18d2a257ab39eee35480efb8307f9513a48f80330332146d20 | --radius 0.3 --boundary free --seed 0
e813b13f1c7f9ea78f0e0d7f1c15026f1e9c0ad03dbb09ebf2cad77d91f7744b | --rf 0.01 --rc 0.02 --seed 1
a29a26253330093a3601b3c46805546084a0577a86f686819588cdec4c5db03d | --rf 0.005 --rc 0.01 --boundary free --seed 2
d2f72688f8287e3bc31e03e249eced828a03c0f1558fb9e12ab24409c2fcc2d3 | --rf 0.01 --rc 0.011 --seed 3
39a4f22ca35ba3ef170d9f89ca13589060a3e4d485aabc2a2adc2cb4e417e22f | --rf 0.01 --rc 0.04 --extent 2,1 --seed 4
aeb0c3ec6bb26cba695373bfc0a4eb894ec33e404d908ec45f2902229d5f0f99 | --rf 0.02 --rc 0.03 --extent 1.5,1 --boundary free --seed 5
3be2ba203644358cb0c3bf6849a97cdd3e8f0e517e538a371e3c4c76c1b48ccf | --rf 2 --rc 3 --extent 160,90 --seed 6
51d1c63d86a54b8f2f8b8221b4307dbab453fbd3f288f861c49c98c7686aa83d | --radius 0.01 --hierarchy discrete:10 --seed 9
d4a5705704c67a85e1afe053a6b82ff780958e8d146e859ea42ca29720707a27 | --radius 0.01 --hierarchy discrete:5 --boundary free --extent 1.2,1 --seed 4
45339365e1437a41d93a51332331367985ec45ee68cf25831faa787ff0f1fa9c | --sizing 0.01+0.05*x --rule smaller --boundary free --seed 1
eb1476994a4e259e5d30721c08227381e59a856510b02409b9de52b006c7fe63 | --sizing 0.02+0.01*sin(2*pi*x)*cos(2*pi*y) --rule prior --seed 2
9f0e6816fa9afc89c696875077a011067728f106660b962826b914a3a32b1972 | --sizing 0.004+0.02*d --rule bigger --weighting density --seed 3
c0184423ca637f1ab26628202dc69bbc25e404064e712cfe4940ca8584e38d25 | --sizing 0.03+(0.006-0.03)*abs(sin(4*pi*d)) --rule current --extent 2,1 --seed 4
a9a89960d0290fd9da220af96ac096b1a081793009a562dda16f9a08178774c9 | --sizing 0.002+0.04*x*y --rule prior --boundary free --extent 1.5,1 --seed 8
c9c81e5824dd900774447ccd26c979c9b67a9d2767ed6ca3f16fadac1e1535a1 | --sizing 0.3+0.1*sin(2*pi*x) --rule current --seed 7
e93fc60a2d01d4132a37cb1b1ff1a3ca69ccf1f73481dff368c09b7c817af1b2 | --sizing 0.006+0.003*sin(2*pi*x)*cos(2*pi*y) --rule bigger --hierarchy discrete:4:3 --seed 5
985172adab7a4d7826aa3a90c27730e314912f277347f5c51404bc6e2242b999 | --sizing 0.004+0.03*abs(x-0.3) --rule bigger --boundary free --weighting density --seed 10
EOF
)

dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
failed=0
cases=0
# check TABLE DEVICE...: runs each case of TABLE on each device against its hash.
check() {
    local table=$1
    shift
    while IFS='|' read -r want args; do
        want=$(echo "$want" | tr -d ' ')
        for device in "$@"; do
            # shellcheck disable=SC2086
            if ! "$vrpd" sample $args --device "$device" -o "$dir/p.csv" 2> "$dir/err"; then
                echo "FAIL: sample $args --device $device: $(cat "$dir/err")"
                failed=$((failed + 1))
                continue
            fi
            got=$(sha256sum "$dir/p.csv" | cut -d' ' -f1)
            cases=$((cases + 1))
            if [ $print = 1 ]; then
                echo "$got | $args   ($device)"
            elif [ "$got" != "$want" ]; then
                echo "FAIL: sample $args --device $device: sha256 $got, table says $want"
                failed=$((failed + 1))
            fi
        done
    done <<< "$table"
}
check "$table" "${devices[@]}"
[ $print = 1 ] && exit 0
echo "golden hashes: $((cases - failed)) passed, $failed failed"
[ $failed = 0 ] && [ $cases -gt 0 ]
