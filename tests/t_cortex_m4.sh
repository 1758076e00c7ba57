#!/bin/sh
# core/ (the Delaunay core and the planner) compiles and links freestanding for a Cortex-M4
# (arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -Os, with the microcontroller option VP_CORE_MCU
# of core/vp_status.h) into boards/cortex-m4's image with a static arena and a built-in
# simulated probe; prints the .text size of the core and the image's flash and RAM use with
# the planner linked. The firmware's scan loop also runs on the build machine
# (-DVP_M4_HOST, same sources, same arena) and must reach DONE: the arena is large enough.
set -eu
B=${BUILD:-build}
command -v arm-none-eabi-gcc >/dev/null || { echo "arm-none-eabi-gcc missing (make deps)"; exit 1; }
O="$B/m4"; mkdir -p "$O"
CF="-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -Os -ffreestanding -std=c99 -pedantic
    -Wall -Wextra -Werror -Wmissing-prototypes -Wshadow -ffp-contract=off -fno-math-errno
    -ffunction-sections -fdata-sections -Icore -DVP_CORE_MCU"
objs=""
# the planner as one unit (core/planner/unity: its shared functions static, as in one file)
for c in core/*.c core/planner/unity/vp_planner_unity.c; do
  o="$O/$(basename "$c" .c).o"
  arm-none-eabi-gcc $CF -c "$c" -o "$o"
  objs="$objs $o"
done
arm-none-eabi-gcc $(echo $CF | sed "s/-pedantic//") -c boards/cortex-m4/firmware.c -o "$O/firmware.o"
arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -nostartfiles \
  --specs=nano.specs -Wl,--gc-sections -Wl,-Map="$O/voroprobe-m4.map" -T boards/cortex-m4/link.ld \
  -o "$O/voroprobe-m4.elf" "$O/firmware.o" $objs -lm
# the planner must be in the image, not dropped by --gc-sections
for f in vp_planner_init vp_planner_next vp_planner_feed vp_dt_insert; do
  arm-none-eabi-nm "$O/voroprobe-m4.elf" | grep -q " T $f\$" || { echo "$f is not linked into the image"; exit 1; }
done
text=$(arm-none-eabi-size -t $objs | awk 'END {print $1}')
ptext=$(arm-none-eabi-size "$O/vp_planner_unity.o" | awk 'NR==2 {print $1}')
arena=$(printf "%d" "0x$(arm-none-eabi-nm -S "$O/voroprobe-m4.elf" | awk '$4 == "arena" {print $2}')")
set -- $(arm-none-eabi-size "$O/voroprobe-m4.elf" | awk 'NR==2 {print $1, $2, $3}')
flash=$(( $1 + $2 )); ram=$(( $2 + $3 ))
# the same loop on the build machine
gcc -std=c99 -O2 -ffp-contract=off -DVP_M4_HOST -DVP_CORE_MCU -Icore boards/cortex-m4/firmware.c core/*.c core/planner/unity/vp_planner_unity.c -lm -o "$O/firmware-host"
run=$("$O/firmware-host") || { echo "$run"; echo "the firmware's scan loop did not reach DONE"; exit 1; }
echo "$run"
echo "cortex-m4: core .text $text bytes ($(echo $objs | wc -w) objects, planner $ptext); image with the planner flash $flash bytes, RAM $ram bytes (static arena ${arena:-?} bytes included)"
