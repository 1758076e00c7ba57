#!/bin/sh
# Builds the MCU scanner (boards/cortex-m4/mcu_*.c) twice from the same sources:
#   BUILD/m4/voroprobe-an386.elf   the Cortex-M4 image for the MPS2 AN386
#                                  (qemu-system-arm -M mps2-an386 -kernel ..., or the board)
#   BUILD/m4/voroprobe-m4-host     the build machine's program, the link on stdin/stdout
#                                  (voroprobe mcu --exec)
# and for the STM32F405 (128 KiB of SRAM), with its smaller arena:
#   BUILD/m4/voroprobe-stm32f405.elf    (qemu-system-arm -M netduinoplus2 -kernel ..., or the
#                                       Netduino Plus 2)
#   BUILD/m4/voroprobe-stm32f405-host   the same sources and arena on the build machine
# Usage: sh boards/cortex-m4/build.sh [BUILD]   (default: $BUILD or build). Prints each image's
# flash and RAM (arm-none-eabi-size) and its static arena. VP_MCU_ARENA=BYTES sets the arena of
# the AN386 builds (default 458752: 448 KiB; the AN386 has 4 MiB of data RAM), VP_STM_ARENA
# that of the STM32F405 builds (default 102400: 100 KiB).
set -eu
B=${1:-${BUILD:-build}}
D=boards/cortex-m4
O="$B/m4"; mkdir -p "$O/an386" "$O/host" "$O/stm32f405"
command -v arm-none-eabi-gcc >/dev/null || { echo "build.sh: arm-none-eabi-gcc missing (make deps)" >&2; exit 1; }
ARENA="-DVP_MCU_ARENA_BYTES=${VP_MCU_ARENA:-458752}u"
STM_ARENA="-DVP_MCU_ARENA_BYTES=${VP_STM_ARENA:-102400}u"
WARN="-std=c99 -Wall -Wextra -Werror -Wmissing-prototypes -Wshadow"
FP="-ffp-contract=off -fno-math-errno"
MCU_SRC="$D/mcu_link.c $D/mcu_motion.c $D/mcu_scan.c"
CF0="-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -Os -ffreestanding $WARN $FP
    -ffunction-sections -fdata-sections -Icore -include $D/mcu.h ${VP_MCU_CORE_OPT--DVP_CORE_MCU}"
CF="$CF0 $ARENA"
objs=""
for c in core/*.c core/planner/unity/vp_planner_unity.c; do
  o="$O/an386/$(basename "$c" .c).o"
  arm-none-eabi-gcc $CF -pedantic -c "$c" -o "$o"
  objs="$objs $o"
done
for c in $MCU_SRC $D/mcu_start.c $D/board_an386.c; do
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
# the STM32F405: the core's objects are the same (no arena in them); the MCU's own files again
sobjs=""
for o in $objs; do case $o in */mcu_*.o|*/board_*.o) ;; *) sobjs="$sobjs $o" ;; esac; done
for c in $MCU_SRC $D/mcu_start.c $D/board_stm32f405.c; do
  o="$O/stm32f405/$(basename "$c" .c).o"
  arm-none-eabi-gcc $CF0 $STM_ARENA -pedantic -c "$c" -o "$o"
  sobjs="$sobjs $o"
done
arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -nostartfiles \
  --specs=nano.specs -Wl,--gc-sections -Wl,-Map="$O/voroprobe-stm32f405.map" -T $D/stm32f405.ld \
  -o "$O/voroprobe-stm32f405.elf" $sobjs -lm
gcc $WARN -pedantic $FP -O2 -D_POSIX_C_SOURCE=200809L -Icore -include $D/mcu.h $STM_ARENA ${VP_MCU_CORE_OPT--DVP_CORE_MCU} \
  -o "$O/voroprobe-stm32f405-host" $MCU_SRC $D/board_hostpipe.c core/*.c core/planner/unity/vp_planner_unity.c -lm
for img in an386:mps2-an386 stm32f405:stm32f405; do
  elf="$O/voroprobe-${img%%:*}.elf"
  set -- $(arm-none-eabi-size "$elf" | awk 'NR==2 {print $1, $2, $3}')
  arena=$(printf "%d" "0x$(arm-none-eabi-nm -S "$elf" | awk '$4 == "arena" {print $2}')")
  echo "${img#*:} image: flash $(( $1 + $2 )) bytes (text $1, data $2), RAM $(( $2 + $3 )) bytes (static arena $arena bytes included)"
done
