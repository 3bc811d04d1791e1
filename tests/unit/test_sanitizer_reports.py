"""make asan's verdict (benchmarks/sanitizer_reports.py) on sanitizer logs written the way
ASan, UBSan and LeakSanitizer write them: our errors and leaks count, Python's do not."""
from benchmarks.sanitizer_reports import classify

PYTHON_LEAK = """Direct leak of 536 byte(s) in 1 object(s) allocated from:
    #0 0x7f1e2dab89cf in __interceptor_malloc ../../../../src/libsanitizer/asan/asan_malloc_linux.cpp:69
    #1 0x7f1e2d5af897 in _PyObject_Malloc Objects/obmalloc.c:2003
    #2 0x7f1e2b51b46f  (<unknown module>)
"""
OUR_LEAK = """Direct leak of 48 byte(s) in 1 object(s) allocated from:
    #0 0x7f1e2dab89cf in __interceptor_calloc ../../../../src/libsanitizer/asan/asan_malloc_linux.cpp:77
    #1 0x7f0 in asm_config_read /work/x/assemblies/engine/fmu/assembly_config.c:212
    #2 0x7f1 in mf_create /work/x/assemblies/engine/fmu/assembly_runtime.c:200
"""
UNLOADED_LEAK = """Indirect leak of 8 byte(s) in 1 object(s) allocated from:
    #0 0x7f1e2dab89cf in __interceptor_malloc ../../../../src/libsanitizer/asan/asan_malloc_linux.cpp:69
    #1 0x7f1e28d9932f  (<unknown module>)
"""
ASAN_ERROR = """=================================================================
==8695==ERROR: AddressSanitizer: heap-buffer-overflow on address 0x6020 at pc 0x7f bp 0x7f
READ of size 8 at 0x6020 thread T0
    #0 0x7f in access /work/x/assemblies/engine/fmu/assembly_runtime.c:365
"""
UBSAN = "/work/x/assemblies/engine/c/jacobian.c:83:9: runtime error: null pointer passed as argument 2\n"


def test_only_our_leaks_and_every_error_count():
    log = ("=================================================================\n"
           "==1==ERROR: LeakSanitizer: detected memory leaks\n\n"
           + "\n".join([PYTHON_LEAK, OUR_LEAK, UNLOADED_LEAK]))
    found = classify(log)
    assert len(found["leaks"]) == 2
    assert "asm_config_read" in found["leaks"][0] and "unknown module" in found["leaks"][1]
    assert not found["asan"] and not found["ubsan"]
    found = classify(ASAN_ERROR + UBSAN)
    assert len(found["asan"]) == 1 and "heap-buffer-overflow" in found["asan"][0]
    assert len(found["ubsan"]) == 1 and "null pointer" in found["ubsan"][0]
    assert classify(PYTHON_LEAK) == {"asan": [], "ubsan": [], "leaks": []}
