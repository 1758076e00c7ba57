#!/bin/sh
# Builds the MCU scanner (boards/cortex-m4/mcu_*.c) twice from the same sources:
#   BUILD/m4/voroprobe-an386.elf   the Cortex-M4 image for the MPS2 AN386
#                                  (qemu-system-arm -M mps2-an386 -kernel ..., or the board)
#   BUILD/m4/voroprobe-m4-host     the build machine's program, the link on stdin/stdout
#                                  (voroprobe mcu --exec)
# Usage: sh boards/cortex-m4/build.sh [BUILD]   (default: $BUILD or build). Prints the image's
# flash and RAM (arm-none-eabi-size) and its static arena. VP_MCU_ARENA=BYTES sets the arena of
# both builds (default 458752: 448 KiB; the AN386 has 4 MiB of data RAM).
set -eu
B=${1:-${BUILD:-build}}
D=boards/cortex-m4
O="$B/m4"; mkdir -p "$O/an386" "$O/host"
command -v arm-none-eabi-gcc >/dev/null || { echo "build.sh: arm-none-eabi-gcc missing (make deps)" >&2; exit 1; }
ARENA="-DVP_MCU_ARENA_BYTES=${VP_MCU_ARENA:-458752}u"
WARN="-std=c99 -Wall -Wextra -Werror -Wmissing-prototypes -Wshadow"
FP="-ffp-contract=off -fno-math-errno"
MCU_SRC="$D/mcu_link.c $D/mcu_motion.c $D/mcu_scan.c"
CF="-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -Os -ffreestanding $WARN $FP
    -ffunction-sections -fdata-sections -Icore -include $D/mcu.h $ARENA ${VP_MCU_CORE_OPT--DVP_CORE_MCU}"
objs=""
for c in core/*.c core/planner/unity/vp_planner_unity.c; do
  o="$O/an386/$(basename "$c" .c).o"
  arm-none-eabi-gcc $CF -pedantic -c "$c" -o "$o"
  objs="$objs $o"
done
for c in $MCU_SRC $D/board_an386.c; do
  o="$O/an386/$(basename "$c" .c).o"
  arm-none-eabi-gcc $CF -pedantic -c "$c" -o "$o"
  objs="$objs $o"
done
arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -nostartfiles \
  --specs=nano.specs -Wl,--gc-sections -Wl,-Map="$O/voroprobe-an386.map" -T $D/an386.ld \
  -o "$O/voroprobe-an386.elf" $objs -lm
# the same sources on this machine
gcc $WARN -pedantic $FP -O2 -D_POSIX_C_SOURCE=200809L -Icore -include $D/mcu.h $ARENA ${VP_MCU_CORE_OPT--DVP_CORE_MCU} \
  -o "$O/voroprobe-m4-host" $MCU_SRC $D/board_hostpipe.c core/*.c core/planner/unity/vp_planner_unity.c -lm
set -- $(arm-none-eabi-size "$O/voroprobe-an386.elf" | awk 'NR==2 {print $1, $2, $3}')
arena=$(printf "%d" "0x$(arm-none-eabi-nm -S "$O/voroprobe-an386.elf" | awk '$4 == "arena" {print $2}')")
echo "mps2-an386 image: flash $(( $1 + $2 )) bytes (text $1, data $2), RAM $(( $2 + $3 )) bytes (static arena $arena bytes included)"
