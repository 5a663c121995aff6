#!/usr/bin/env bash
# Rebuilds the hurricane replays of configs/scenarios/ (README.md there, "How the replays were
# made") from the NHC best-track rows in tests/data/ with gale-hurdat: Andrew and Charley from
# hurdat2-andrew1992-charley2004.txt, the storm library from hurdat2-landfalls.txt. Each
# replay: the storm's rows around its strongest landfall on the US or Puerto Rico coast (t = 0
# at that L row), a site 1-6 km from the track, a window around the eye's passage and a time
# scale that replays it in about 6-7.5 minutes. Writes DIR/<stem>.json (default
# configs/scenarios); tests/test_storm_library.c checks the shipped files equal its output.
# Usage: deploy/storm-library.sh [DIR]   (GALE_HURDAT: the tool, default
# $GALE_BUILD/server/gale-hurdat, GALE_BUILD: the build folder, default build)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = --help ] || [ "${1:-}" = -h ]; then
    echo "usage: deploy/storm-library.sh [DIR]"
    sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'
    exit 0
fi
out="${1:-configs/scenarios}"
hurdat="${GALE_HURDAT:-${GALE_BUILD:-build}/server/gale-hurdat}"
[ -x "$hurdat" ] || { echo "storm-library: $hurdat is needed (deploy/build.sh)" >&2; exit 2; }
mkdir -p "$out"

# replay IN ID NAME REF FROM TO LAT LON LABEL SCALE START END SEED UTC_OFFSET STEM
replay() {
    "$hurdat" --in "$1" --storm "$2" --name "$3" --ref "$4" --from "$5" --to "$6" \
        --site-lat "$7" --site-lon "$8" --site-label "$9" --time-scale "${10}" \
        --start-min "${11}" --end-min "${12}" --seed "${13}" --utc-offset-min "${14}" \
        --out "$out/${15}.json"
}

A=tests/data/hurdat2-andrew1992-charley2004.txt
L=tests/data/hurdat2-landfalls.txt
# Local time: EDT (-240) on the Atlantic coast and the Keys, CDT (-300) on the Gulf west of
# the Apalachicola (Mexico Beach keeps Central time), AST (-240) in Puerto Rico; Labor Day
# 1935: EST (-300), the Keys kept no daylight time then.
#      in id       name        ref (L row)       from              to                lat    lon     label                                                scale start end  seed offset stem
replay $A ANDREW   Andrew      1992-08-24T09:05Z 1992-08-24T06:00Z 1992-08-24T12:00Z 25.52 -80.40 "south Miami-Dade County, Florida, in the eye's path" 50 -160 175 1992 -240 andrew1992
replay $A CHARLEY  Charley     2004-08-13T19:45Z 2004-08-13T18:00Z 2004-08-14T00:00Z 26.93 -82.06 "Punta Gorda, Florida, in the eye's path" 30 -45 150 2004 -240 charley2004
replay $L AL031935 "Labor Day" 1935-09-03T02:00Z 1935-09-03T00:00Z 1935-09-03T06:00Z 24.81 -80.79 "Long Key, Florida Keys, in the eye's path" 40 -110 130 1935 -300 laborday1935
replay $L AL091969 Camille     1969-08-18T04:00Z 1969-08-18T00:00Z 1969-08-18T06:00Z 30.29 -89.38 "Waveland, Mississippi, in the eye's path" 30 -100 90 1969 -300 camille1969
replay $L AL111989 Hugo        1989-09-22T04:00Z 1989-09-22T00:00Z 1989-09-22T12:00Z 32.81 -79.79 "Mount Pleasant, South Carolina, in the eye's path" 50 -160 145 1989 -240 hugo1989
replay $L AL122005 Katrina     2005-08-29T11:10Z 2005-08-29T06:00Z 2005-08-29T18:00Z 29.33 -89.58 "near Buras, Louisiana, in the eye's path" 80 -270 260 2005 -300 katrina2005
replay $L AL252005 Wilma       2005-10-24T10:30Z 2005-10-24T06:00Z 2005-10-24T18:00Z 25.93 -81.71 "Marco Island, Florida, in the eye's path" 60 -200 175 2005 -240 wilma2005
replay $L AL092008 Ike         2008-09-13T07:00Z 2008-09-12T18:00Z 2008-09-13T18:00Z 29.31 -94.72 "Galveston, Texas, in the eye's path" 120 -465 430 2008 -300 ike2008
replay $L AL092017 Harvey      2017-08-26T03:00Z 2017-08-25T18:00Z 2017-08-26T12:00Z 28.06 -97.03 "Rockport, Texas, in the eye's path" 100 -265 400 2017 -300 harvey2017
replay $L AL112017 Irma        2017-09-10T13:00Z 2017-09-10T06:00Z 2017-09-10T18:00Z 24.67 -81.49 "Cudjoe Key, Florida Keys, in the eye's path" 50 -165 150 2017 -240 irma2017
replay $L AL152017 Maria       2017-09-20T10:15Z 2017-09-20T06:00Z 2017-09-20T18:00Z 18.05 -65.88 "Yabucoa, Puerto Rico, in the eye's path" 60 -215 210 2017 -240 maria2017
replay $L AL142018 Michael     2018-10-10T17:30Z 2018-10-10T12:00Z 2018-10-11T00:00Z 29.99 -85.48 "near Mexico Beach, Florida, in the eye's path" 30 -120 95 2018 -300 michael2018
replay $L AL132020 Laura       2020-08-27T06:00Z 2020-08-27T00:00Z 2020-08-27T12:00Z 29.80 -93.28 "near Cameron, Louisiana, in the eye's path" 60 -200 190 2020 -300 laura2020
replay $L AL092021 Ida         2021-08-29T16:55Z 2021-08-29T12:00Z 2021-08-30T00:00Z 29.11 -90.19 "Port Fourchon, Louisiana, in the eye's path" 50 -175 165 2021 -300 ida2021
replay $L AL092022 Ian         2022-09-28T19:05Z 2022-09-28T12:00Z 2022-09-29T06:00Z 26.69 -82.23 "Cayo Costa, Florida, in the eye's path" 120 -425 410 2022 -240 ian2022
